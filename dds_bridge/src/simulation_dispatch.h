// One simulation-control request run against the runner: pause, run, real-time factor, steps,
// status. No DDS here: SimulationServer calls it on the simulation thread (loads it queues as
// loads itself), unit tests and the fuzzer call it directly.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "macsim/msg/macsim_msgs.h"
#include "macsim/sim_core/runner.h"
#include "step_conditions.h"

namespace macsim {

/// The reply to `request` with `code` and `message`, stamped with the runner's time, steps,
/// state hash, pause flag, real-time factor and features.
macsim_msgs::msg::dds_::SimulationReply_ simulation_reply(
    const macsim_msgs::msg::dds_::SimulationRequest_& request, const Runner& runner, int code,
    const std::string& message);

/// Applies the request to the runner. The reply now, or nothing for a step request that was
/// taken: `stepped` receives its reply once the last step is done (or a pause cancelled it).
/// A step request's robot conditions read `readings` (none: they are refused); its steps done
/// are counted in `steps_done` (if given), which other threads may read while it runs.
std::optional<macsim_msgs::msg::dds_::SimulationReply_> dispatch_simulation(
    const macsim_msgs::msg::dds_::SimulationRequest_& request, Runner& runner,
    std::function<void(const macsim_msgs::msg::dds_::SimulationReply_&)> stepped,
    const LatestReadings& readings = {},
    std::shared_ptr<std::atomic<uint64_t>> steps_done = nullptr);

}  // namespace macsim
