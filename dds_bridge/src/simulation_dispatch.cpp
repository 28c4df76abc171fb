#include "simulation_dispatch.h"

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
  r.features(
      "simulator,supervisor,lockstep,ground_truth,reset,snapshot,load_world,cameras,laser,crane");
  return r;
}

std::optional<mm::SimulationReply_> dispatch_simulation(
    const mm::SimulationRequest_& q, Runner& runner,
    std::function<void(const mm::SimulationReply_&)> stepped) {
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
      if (q.steps() == 0) break;  // zero steps: answered at once
      const bool taken =
          runner.request_steps(q.steps(), [&runner, q, stepped = std::move(stepped)](bool done) {
            stepped(done ? simulation_reply(q, runner, mm::ERR_OK, "")
                         : simulation_reply(q, runner, mm::ERR_NOT_APPLICABLE,
                                            "cancelled: paused by SIM_PAUSE, or by a body "
                                            "that went unstable (see the events)"));
          });
      if (!taken) {
        return simulation_reply(q, runner, mm::ERR_INVALID_ARGUMENT,
                                "a step request is still running");
      }
      return std::nullopt;  // answered when its last step's data is out
    }
    case mm::SIM_FEATURES:
    case mm::SIM_STATUS:
      break;
    default:
      return simulation_reply(q, runner, mm::ERR_UNKNOWN_OPERATION,
                              "unknown simulation command " + std::to_string(q.command()));
  }
  return simulation_reply(q, runner, mm::ERR_OK, "");
}

}  // namespace macsim
