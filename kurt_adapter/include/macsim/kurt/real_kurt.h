// The real KURT3D behind the one robot interface: commands become the driver's set-points and
// CAN frames; the microcontroller's frames become readings. What RobotNode serves for the robot.
#pragma once

#include <functional>
#include <string>

#include "macsim/kurt/can_frame.h"
#include "macsim/kurt/kurt_driver.h"
#include "macsim/robot/robot_interface.h"

namespace macsim::kurt {

/// The KURT on a CAN bus: odometry and wheel joints, IR/sonar, gyro and tilt, the rotunit and
/// the magnet (on the actuator output). It has no crane joints, laser or ground truth here
/// (the laser has a driver of its own on the robot).
class RealKurt : public robot::RobotInterface {
 public:
  /// `clock`: seconds of a monotonic clock (the command timeout runs on it); `stamp`: seconds
  /// of the wall clock (message stamps, as the real driver stamps with ROS time).
  RealKurt(std::string name, KurtDriver& driver, CanTransport& can, std::function<double()> clock,
           std::function<double()> stamp);

  /// Integrates one frame from the robot; what it updated is new at the next read().
  void handle(const CanFrame& frame);

  std::string name() const override { return name_; }
  robot::Capabilities capabilities() const override;
  /// A twist or wheel speeds to the driver (SPEED_CM at the next tick); a rotunit speed as
  /// SETROTUNIT at once; the magnet as the actuator output at once (CONTROL ACTUATOR_ON /
  /// ACTUATOR_OFF). The crane is not on this robot's bus: refused, as anything else.
  bool execute(const robot::RobotCommand& command) override;
  robot::Readings read() override;
  /// base_link above base_footprint and the eight IR/sonar sensors (kurt_driver's URDF).
  robot::Frames frames() const override;

 private:
  std::string name_;
  KurtDriver& driver_;
  CanTransport& can_;
  std::function<double()> clock_, stamp_;
  robot::Readings pending_;
  double last_yaw_ = 0.0, last_imu_time_ = 0.0;
};

}  // namespace macsim::kurt
