#include "macsim/robot/mock_robot.h"

#include <cmath>

namespace macsim::robot {

MockRobot::MockRobot(std::string name, Capabilities capabilities, double track,
                     double command_timeout)
    : name_(std::move(name)),
      capabilities_(capabilities),
      track_(track),
      command_timeout_(command_timeout) {}

void MockRobot::drive(double linear, double angular) {
  linear_ = linear;
  angular_ = angular;
  last_command_ = now_;
}

bool MockRobot::execute(const RobotCommand& command) {
  if (const auto* t = command.as<Twist>()) {
    drive(t->linear, t->angular);
  } else if (const auto* w = command.as<WheelSpeedCommand>()) {
    drive((w->left + w->right) / 2, (w->right - w->left) / track_);
  } else if (const auto* r = command.as<RotunitSpeed>(); r && capabilities_.rotunit) {
    rotunit_.speed = r->speed;
  } else if (const auto* c = command.as<CraneTarget>(); c && capabilities_.crane) {
    crane_.slew = c->slew;
    crane_.lift = c->lift;
    crane_.hoist = c->hoist;
  } else if (const auto* m = command.as<MagnetSwitch>(); m && capabilities_.magnet) {
    crane_.magnet_on = m->on;
  } else {
    return false;
  }
  return true;
}

void MockRobot::advance(double now) {
  const double dt = now - now_;
  now_ = now;
  if (dt <= 0) return;
  const bool driving = now - last_command_ <= command_timeout_;
  const double v = driving ? linear_ : 0.0, w = driving ? angular_ : 0.0;
  odometry_.x += v * std::cos(odometry_.yaw) * dt;
  odometry_.y += v * std::sin(odometry_.yaw) * dt;
  odometry_.yaw = std::remainder(odometry_.yaw + w * dt, 2 * M_PI);
  odometry_.linear = v;
  odometry_.angular = w;
  odometry_.left_wheel =
      std::remainder(odometry_.left_wheel + (v - w * track_ / 2) * dt / 0.06, 2 * M_PI);
  odometry_.right_wheel =
      std::remainder(odometry_.right_wheel + (v + w * track_ / 2) * dt / 0.06, 2 * M_PI);
  rotunit_.angle = std::fmod(rotunit_.angle + rotunit_.speed * dt, 2 * M_PI);
  moved_ = true;
}

Readings MockRobot::read() {
  Readings r;
  r.stamp = now_;
  if (!moved_) return r;
  moved_ = false;
  r.odometry = odometry_;
  if (capabilities_.ranges) r.ranges = ranges_;
  if (capabilities_.imu) r.imu = Imu{0, 0, odometry_.yaw, 0, odometry_.angular};
  if (capabilities_.rotunit) r.rotunit = rotunit_;
  if (capabilities_.crane) r.crane = crane_;
  return r;
}

}  // namespace macsim::robot
