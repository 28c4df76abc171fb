#include "macsim/kurt/real_kurt.h"

#include <cmath>

#include "macsim/kurt/kurt_can.h"
#include "macsim/robot/kurt3d_description.h"

namespace macsim::kurt {

RealKurt::RealKurt(std::string name, KurtDriver& driver, CanTransport& can,
                   std::function<double()> clock, std::function<double()> stamp)
    : name_(std::move(name)),
      driver_(driver),
      can_(can),
      clock_(std::move(clock)),
      stamp_(std::move(stamp)) {}

robot::Capabilities RealKurt::capabilities() const {
  robot::Capabilities c;
  c.ranges = c.imu = c.rotunit = c.magnet = true;
  return c;
}

robot::Frames RealKurt::frames() const {
  robot::Frames f;
  f.mounts.push_back({"base_footprint",
                      "base_link",
                      {0, 0, robot::kurt3d::kBaseLinkAboveWheelAxle + driver_.params().wheel_radius()},
                      {0, 0, 0, 1}});
  for (const robot::kurt3d::RangeSensor& s : robot::kurt3d::kRangeSensors) {
    f.mounts.push_back(
        {"base_link", s.frame, {s.x, s.y, 0}, {0, 0, std::sin(s.yaw / 2), std::cos(s.yaw / 2)}});
  }
  f.description = robot::kurt3d::description_text();
  return f;
}

bool RealKurt::execute(const robot::RobotCommand& command) {
  if (const auto* t = command.as<robot::Twist>()) {
    driver_.command_twist(t->linear, t->angular, clock_());
  } else if (const auto* w = command.as<robot::WheelSpeedCommand>()) {
    driver_.command_wheel_speeds({w->left, w->right}, clock_());
  } else if (const auto* r = command.as<robot::RotunitSpeed>()) {
    can_.send(driver_.command_rotunit(r->speed));
  } else if (const auto* m = command.as<robot::MagnetSwitch>()) {
    // Assumption (kurt_adapter/README.md): the crane's magnet hangs on the controller's
    // actuator output, switched by CONTROL ACTUATOR_ON / ACTUATOR_OFF.
    can_.send(encode_actuator(m->on));
  } else {
    return false;
  }
  return true;
}

void RealKurt::handle(const CanFrame& frame) {
  const double stamp = stamp_();
  switch (driver_.handle(frame)) {
    case Update::Odometry: {
      const auto o = driver_.odometry();
      pending_.odometry = robot::Odometry{
          o.x, o.y, o.yaw, o.linear, o.angular, driver_.wheel_angle(0), driver_.wheel_angle(1)};
      break;
    }
    case Update::Ranges:
      pending_.ranges.clear();
      for (std::size_t i = 0; i < kRangeChannels.size(); ++i) {
        pending_.ranges.push_back(
            {kRangeChannels[i].frame, kRangeChannels[i].sonar, driver_.ranges()[i]});
      }
      break;
    case Update::Imu: {
      const auto gyro = *driver_.gyro();
      const auto tilt = driver_.tilt().value_or(Tilt{});
      const double dt = last_imu_time_ > 0 ? stamp - last_imu_time_ : 0.0;
      const double rate = dt > 0 ? std::remainder(gyro.yaw - last_yaw_, 2 * M_PI) / dt : 0.0;
      last_yaw_ = gyro.yaw;
      last_imu_time_ = stamp;
      pending_.imu = robot::Imu{tilt.roll_deg * M_PI / 180, tilt.pitch_deg * M_PI / 180, gyro.yaw,
                                gyro.variance, rate};
      break;
    }
    case Update::Rotunit:
      pending_.rotunit = robot::Rotunit{*driver_.rotunit_angle(), driver_.rotunit_speed()};
      break;
    default:
      return;
  }
  pending_.stamp = stamp;
}

robot::Readings RealKurt::read() {
  robot::Readings out = std::move(pending_);
  pending_ = robot::Readings{};
  return out;
}

}  // namespace macsim::kurt
