#include "robot_commands.h"

#include <cmath>

namespace macsim::robot_commands {

namespace {
/// Runs `act` on the robot of that name in the world current when the command runs.
template <class Act>
Command on_robot(const std::string& robot, Act act) {
  return [robot, act](World& world) {
    if (KurtRobot* r = world.robot(robot)) act(*r, world);
  };
}
}  // namespace

std::optional<Command> twist(const std::string& robot, double linear, double angular) {
  if (!std::isfinite(linear) || !std::isfinite(angular)) return std::nullopt;  // never into ODE
  return on_robot(robot, [linear, angular](KurtRobot& r, World& w) {
    r.command_twist(linear, angular, w.time());
  });
}

std::optional<Command> wheel_speeds(const std::string& robot, WheelSpeeds speeds) {
  if (!std::isfinite(speeds.left) || !std::isfinite(speeds.right)) return std::nullopt;
  return on_robot(robot, [speeds](KurtRobot& r, World& w) { r.command_wheel_speeds(speeds, w.time()); });
}

std::optional<Command> rotunit(const std::string& robot, double speed) {
  if (!std::isfinite(speed)) return std::nullopt;
  return on_robot(robot, [speed](KurtRobot& r, World&) { r.command_rotunit(speed); });
}

std::optional<Command> crane(const std::string& robot, const CraneCommand& target) {
  if (!std::isfinite(target.slew) || !std::isfinite(target.lift) || !std::isfinite(target.hoist)) {
    return std::nullopt;
  }
  return on_robot(robot, [target](KurtRobot& r, World&) { r.command_crane(target); });
}

Command magnet(const std::string& robot, bool on) {
  return on_robot(robot, [on](KurtRobot& r, World&) { r.command_magnet(on); });
}

}  // namespace macsim::robot_commands
