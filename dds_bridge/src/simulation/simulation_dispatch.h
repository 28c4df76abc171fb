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
#include "macsim/sim_core/world_loader.h"
#include "simulation/step_conditions.h"

namespace macsim {

/// A world a request loads: a file or, when `file` is empty, the text of one.
struct WorldSource {
  std::string file;
  std::string xml;
};

/// How every request that loads a world (SIM_LOAD_WORLD, LoadWorld, a replay) parses it: on
/// the runner's loader thread, through the runner's data roots, held to `limits`.
std::function<WorldSpec()> world_parser(const Runner& runner, LoadLimits limits,
                                        WorldSource source);
/// Queues that load on the runner; a session records it as the command load_command() makes.
/// No robot command in `sent_before` acts on the new world (Command::sent_before).
LoadQueued queue_world_load(Runner& runner, LoadLimits limits, WorldSource source,
                            std::function<void(const LoadOutcome&)> done,
                            std::vector<Sender> sent_before = {});
/// The command a session records for a load (load_world: the file; load_world_xml: the text).
Command load_command(const WorldSource& source);
/// The load a recorded command names; nullopt if it names none.
std::optional<WorldSource> load_source(const Command& command);

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
    std::shared_ptr<std::atomic<uint64_t>> steps_done = nullptr,
    std::function<void()> first_step = {});

}  // namespace macsim
