// Fuzzes the supervisor and simulation-control requests as they come off the wire: records of
// CDR bytes, deserialized by the generated types as every reader of macsim does (through
// dds::CheckedType: a malformed sample is dropped), then run by
// the same dispatch functions macsim's servers call, on the demonstrator world, with steps in
// between. After each record: a reply is always there, what must hold of any world holds, and
// an object id keeps its name (until a reset or restore puts time back). Each run starts from
// the world as loaded.
#include <fastdds/rtps/common/SerializedPayload.h>

#include <cstdio>
#include <cstdlib>
#include <map>

#include "finding.h"
#include "fuzz_input.h"
#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/world_loader.h"
#include "quiet_log.h"
#include "simulation/simulation_dispatch.h"
#include "supervisor/supervisor_dispatch.h"
#include "support/world_invariants.h"

namespace {

namespace mm = macsim_msgs::msg::dds_;

using macsim::fuzz::finding;

/// Deserializes as macsim's readers do: false if the bytes are not a sample of the type.
template <class PubSubType, class Sample>
bool from_wire(std::string_view bytes, Sample& sample) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(uint32_t(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = uint32_t(bytes.size());
  macsim::dds::CheckedType<PubSubType> type;
  return type.deserialize(&payload, &sample);
}

struct Fixture {
  macsim::Runner runner{
      macsim::load_world_file(std::string(MACSIM_SOURCE_DIR) + "/worlds/DemoWorld_v1.xml"),
      macsim::RunSettings{true, 0.0}};
  macsim::WorldSnapshot initial = runner.world().snapshot();
};

}  // namespace

// The loader's warnings for every input would drown the fuzzer's own output.
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  static Fixture fixture;
  macsim::Runner& runner = fixture.runner;
  if (!runner.world().restore(fixture.initial).ok()) finding("the initial snapshot is refused");
  runner.snapshots().clear();
  runner.pause();  // cancels a step request left from the last run
  runner.set_real_time_factor(0.0);
  std::map<macsim::ObjectId, std::string> names;
  for (const auto& record :
       macsim::fuzz::split_records({reinterpret_cast<const char*>(data), size})) {
    macsim::World& world = runner.world();
    if (record.kind % 2 == 0) {
      mm::SupervisorRequest_ request;
      if (!from_wire<mm::SupervisorRequest_PubSubType>(record.bytes, request)) continue;
      const mm::SupervisorReply_ reply = macsim::dispatch(request, world, runner.snapshots());
      if (reply.sequence_number() != request.sequence_number()) finding("a reply went missing");
      const int32_t op = request.operation()._d();
      if (op == mm::OP_RESET || op == mm::OP_RESTORE_SNAPSHOT) names.clear();
    } else {
      mm::SimulationRequest_ request;
      if (!from_wire<mm::SimulationRequest_PubSubType>(record.bytes, request)) continue;
      if (request.command() == mm::SIM_LOAD_WORLD) continue;  // served by the server itself
      auto reply = macsim::dispatch_simulation(request, runner, [](const mm::SimulationReply_&) {});
      if (!reply && !runner.stepping_on_request()) finding("a step request has no reply");
      runner.set_real_time_factor(0.0);  // pacing waits on the wall clock: not fuzzed here
    }
    // Steps as macsim's loop makes them (step requests counted down and answered), paused or
    // not: a step that pauses the runner (a body put back) must not stop the fuzzer.
    for (int i = 0; i < 1 + record.kind / 64; ++i) runner.step(macsim::StepHooks{});
    if (auto broken = macsim::test::invariant_violation(runner.world())) finding(*broken);
    for (const macsim::ObjectId id : runner.world().objects().object_ids()) {
      const std::string& name = runner.world().objects().object(id)->name;
      auto [known, fresh] = names.try_emplace(id, name);
      if (!fresh && known->second != name) finding("object " + std::to_string(id) + " was renamed");
    }
  }
  runner.pause();
  return 0;
}
