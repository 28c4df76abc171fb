// The drive commands every simulated base takes, in one place.
#pragma once

#include "macsim/robot/robot_command.h"

namespace macsim::detail {

/// Runs a twist or wheel speeds on a robot with command_twist() and command_wheel_speeds();
/// false (nothing done) for any other command.
template <class Robot>
bool execute_drive(Robot& robot, const robot::RobotCommand& command, double now) {
  if (const auto* t = command.as<robot::Twist>()) {
    robot.command_twist(t->linear, t->angular, now);
    return true;
  }
  if (const auto* w = command.as<robot::WheelSpeedCommand>()) {
    robot.command_wheel_speeds({w->left, w->right}, now);
    return true;
  }
  return false;
}

}  // namespace macsim::detail
