// The KURT of a runner's world behind the one robot interface: what RobotNode serves for the
// simulator. Call its commands and read() on the simulation thread (from runner commands and
// hooks): they act on the robot of that name in the world current at that moment.
#pragma once

#include <cstdint>
#include <string>

#include "macsim/robot/robot_interface.h"
#include "macsim/sim_core/runner.h"

namespace macsim {

/// A simulated KURT (kurt3d, kurt2, ...) as a RobotInterface.
class SimulatedKurt : public robot::RobotInterface {
 public:
  /// The robot `name` of the runner's world (it must be there).
  SimulatedKurt(Runner& runner, std::string name);

  std::string name() const override { return name_; }
  robot::Capabilities capabilities() const override { return capabilities_; }
  void command_twist(double linear, double angular) override;
  void command_wheel_speeds(double left, double right) override;
  void command_rotunit(double speed) override;
  void command_crane(double slew, double lift, double hoist) override;
  void command_magnet(bool on) override;
  /// What the last steps produced: odometry, ground truth, IMU, ranges and crane with every
  /// encoder frame, a scan (and the rotunit) with every sweep, a cloud with every revolution.
  robot::Readings read() override;
  /// From the robot's model: base_link above base_footprint, the IR/sonar sensors, the stereo
  /// cameras (and their optical frames), the laser, the crane.
  robot::Frames frames() const override { return frame_tree_; }

 private:
  /// The robot in the current world, or nullptr.
  KurtRobot* robot() { return runner_.world().robot(name_); }

  Runner& runner_;
  std::string name_;
  robot::Capabilities capabilities_;
  robot::Frames frame_tree_;
  uint64_t generation_ = 0;  // of the world the counters below belong to
  double last_time_ = 0.0;
  uint64_t frames_ = 0, scans_ = 0, clouds_ = 0;  // what was read last
};

}  // namespace macsim
