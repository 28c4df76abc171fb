// Any robot of a runner's world behind the one robot interface: what RobotNode serves for the
// simulator. Call its commands and read() on the simulation thread (from runner commands and
// hooks): they act on the robot of that name in the world current at that moment.
#pragma once

#include <cstdint>
#include <string>

#include "macsim/robot/robot_interface.h"
#include "macsim/sim_core/runner.h"

namespace macsim {

/// A simulated robot (kurt3d, kurt2, diff_drive, ...) as a RobotInterface.
class SimulatedRobot : public robot::RobotInterface {
 public:
  /// The robot `name` of the runner's world (it must be there).
  SimulatedRobot(Runner& runner, std::string name);

  std::string name() const override { return name_; }
  robot::Capabilities capabilities() const override { return capabilities_; }
  /// The robot's own RobotModel::execute, at the world's time: the simulator's one way in for a
  /// robot command (the runner gives each one here, SimBridge).
  bool execute(const robot::RobotCommand& command) override;
  /// What the steps since the last call produced (RobotModel::read); after a reset, a restore
  /// or a new world (also one before this robot's first read), everything the robot has.
  robot::Readings read() override;
  /// From the robot's description (RobotModel::frames).
  robot::Frames frames() const override { return frame_tree_; }

 private:
  /// The robot in the current world, or nullptr.
  RobotModel* robot() { return runner_.world().robot(name_); }

  Runner& runner_;
  std::string name_;
  robot::Capabilities capabilities_;
  robot::Frames frame_tree_;
  uint64_t generation_ = 0;  // of the world the mark below belongs to
  uint64_t time_origins_ = 0;  // World::time_origin().count the mark below belongs to
  ReadMark mark_;  // what was read last
};

}  // namespace macsim
