#include "simulation/simulation_dispatch.h"

#include <memory>
#include <utility>

#include "supervisor/supervisor_codec.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

mm::SimulationReply_ simulation_reply(const mm::SimulationRequest_& q, const Runner& runner,
                                      int code, const std::string& message) {
  mm::SimulationReply_ r;
  r.client_id(q.client_id());
  r.sequence_number(q.sequence_number());
  r.code(code);
  r.message(message);
  const World& world = runner.world();
  r.sim_time(world.time());
  r.steps(world.steps());
  r.state_hash(world.state_hash());
  r.paused(runner.settings().paused);
  r.real_time_factor(runner.settings().real_time_factor);
  r.ended_by(-1);
  r.steps_asked(q.command() == mm::SIM_STEP ? q.steps() : 0);
  r.features(
      "simulator,supervisor,lockstep,step_until,cancel,progress,ground_truth,reset,snapshot,load_"
      "world,cameras,laser,crane");
  return r;
}

std::optional<mm::SimulationReply_> dispatch_simulation(
    const mm::SimulationRequest_& q, Runner& runner,
    std::function<void(const mm::SimulationReply_&)> stepped, const LatestReadings& readings,
    std::shared_ptr<std::atomic<uint64_t>> steps_done, std::function<void()> first_step) {
  switch (q.command()) {
    case mm::SIM_PAUSE:
      runner.pause();
      break;
    case mm::SIM_RUN:
      runner.resume();
      break;
    case mm::SIM_SET_RTF:
      if (!runner.set_real_time_factor(q.real_time_factor())) {
        return simulation_reply(q, runner, mm::ERR_INVALID_ARGUMENT,
                                "real_time_factor must be 0 (as fast as possible) or at least " +
                                    std::to_string(kMinRealTimeFactor));
      }
      break;
    case mm::SIM_STEP: {
      constexpr uint32_t kKnownOptions = mm::STEP_PUBLISH_AT_END | mm::STEP_NO_CAMERAS |
                                         mm::STEP_HOLD_COMMANDS | mm::STEP_TRACE_HASH;
      if (q.step_options() & ~kKnownOptions) {
        return simulation_reply(q, runner, mm::ERR_INVALID_ARGUMENT,
                                "step_options " + std::to_string(q.step_options()) +
                                    " has bits that are no STEP_* option");
      }
      std::string held;  // the robots STEP_HOLD_COMMANDS holds, comma-separated
      for (const std::string& robot : q.hold_robots()) {
        if (!runner.world().robot(robot)) {
          return simulation_reply(q, runner, mm::ERR_INVALID_ARGUMENT,
                                  "hold_robots names '" + robot.substr(0, 64) +
                                      "', and this world has no robot of that name");
        }
        held += (held.empty() ? "" : ",") + robot;
      }
      auto compiled = StepConditions::compile(q, runner.world(), readings);
      if (auto* error = std::get_if<std::string>(&compiled)) {
        return simulation_reply(q, runner, mm::ERR_INVALID_ARGUMENT, *error);
      }
      if (q.steps() == 0) break;  // zero steps (fields checked): answered at once
      auto conditions =
          std::make_shared<StepConditions>(std::get<StepConditions>(std::move(compiled)));
      StepRequest request;
      request.steps = q.steps();
      request.check_every = q.check_every();
      if (!conditions->empty()) {
        request.until = [conditions](const World& world) { return conditions->check(world); };
      }
      if (!steps_done) steps_done = std::make_shared<std::atomic<uint64_t>>(0);
      steps_done->store(0, std::memory_order_relaxed);
      const bool trace = q.step_options() & mm::STEP_TRACE_HASH;
      request.each_step = [conditions, steps_done, trace,
                           first_step = std::move(first_step)](const World& world) {
        const uint64_t done = steps_done->load(std::memory_order_relaxed) + 1;
        steps_done->store(done, std::memory_order_relaxed);  // written here only
        if (done == 1 && first_step) first_step();
        if (trace) conditions->trace(world);
      };
      request.hold_commands = q.step_options() & mm::STEP_HOLD_COMMANDS;
      request.hold_robots = held;
      request.publish_at_end = q.step_options() & mm::STEP_PUBLISH_AT_END;
      request.cameras = !(q.step_options() & mm::STEP_NO_CAMERAS);
      request.commands_named = codec::senders(q.commands_sent());
      request.done = [&runner, q, conditions, steps_done, stepped](bool done) {
        auto reply = done ? simulation_reply(q, runner, mm::ERR_OK, "")
                          : simulation_reply(q, runner, mm::ERR_NOT_APPLICABLE,
                                             "cancelled: paused (SIM_PAUSE, or a body that "
                                             "went unstable: see the events), or the world was "
                                             "reset or replaced");
        reply.ended_by(done ? conditions->ended_by() : mm::STEP_CANCELLED);
        reply.steps_done(steps_done->load(std::memory_order_relaxed));
        reply.samples(conditions->samples());
        reply.step_trace(conditions->step_trace());
        stepped(reply);
      };
      request.refused = [&runner, q, stepped](const std::string& why) {
        auto reply = simulation_reply(q, runner, mm::ERR_COMMANDS_MISSING, why);
        reply.ended_by(mm::STEP_CANCELLED);
        stepped(reply);
      };
      const bool taken = runner.request_steps(std::move(request));
      if (!taken) {
        return simulation_reply(q, runner, mm::ERR_INVALID_ARGUMENT,
                                "a step request is still running (its client's SIM_CANCEL, or "
                                "SIM_PAUSE, ends it)");
      }
      return std::nullopt;  // answered when its last step's data is out
    }
    case mm::SIM_FEATURES:
    case mm::SIM_STATUS:
      break;
    case mm::SIM_CANCEL:  // the server cancels its clients' requests; here there are none
      return simulation_reply(q, runner, mm::ERR_NOT_APPLICABLE,
                              "no step request of this client is running");
    default:
      return simulation_reply(q, runner, mm::ERR_UNKNOWN_OPERATION,
                              "unknown simulation command " + std::to_string(q.command()));
  }
  return simulation_reply(q, runner, mm::ERR_OK, "");
}

std::function<WorldSpec()> world_parser(const Runner& runner, LoadLimits limits,
                                        WorldSource source) {
  // On the runner's loader thread, which may outlive whoever asked: nothing of them.
  return [source = std::move(source), limits, files = &runner.data_roots()] {
    LoadOptions options;
    options.limits = limits;
    options.files = files;
    return source.file.empty() ? load_world_string(source.xml, "resource_string.xml", options)
                               : load_world_file(source.file, options);
  };
}

LoadQueued queue_world_load(Runner& runner, LoadLimits limits, WorldSource source,
                            std::function<void(const LoadOutcome&)> done,
                            std::vector<Sender> sent_before) {
  Command recorded = load_command(source);
  recorded.sent_before = std::move(sent_before);
  return runner.load(world_parser(runner, limits, std::move(source)), std::move(done),
                     std::move(recorded));
}

Command load_command(const WorldSource& source) {
  auto load = std::make_shared<LoadWorldRequest>();
  load->file = source.file;
  load->xml = source.file.empty() ? source.xml : "";
  Command c;
  c.source = CommandSource::Simulation;
  c.request = std::move(load);
  return c;
}

std::optional<WorldSource> load_source(const Command& c) {
  const auto* load = c.request_as<LoadWorldRequest>();
  if (!load) return std::nullopt;
  return WorldSource{load->file, load->xml};
}

}  // namespace macsim
