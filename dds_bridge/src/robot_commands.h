// A robot's commands as runner commands: what the bridge queues for each message received.
// Non-finite numbers never become a command; a robot missing from the world when the command
// runs (another world was loaded) is skipped.
#pragma once

#include <optional>
#include <string>

#include "macsim/sim_core/runner.h"

namespace macsim::robot_commands {

/// cmd_vel: linear (m/s) and angular (rad/s) speed.
std::optional<Command> twist(const std::string& robot, double linear, double angular);
/// Wheel rim speeds, m/s.
std::optional<Command> wheel_speeds(const std::string& robot, WheelSpeeds speeds);
/// The rotating laser unit's speed, rad/s.
std::optional<Command> rotunit(const std::string& robot, double speed);
/// Crane joint targets.
std::optional<Command> crane(const std::string& robot, const CraneCommand& target);
/// The magnet on or off.
Command magnet(const std::string& robot, bool on);

}  // namespace macsim::robot_commands
