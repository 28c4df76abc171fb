// A mock robot (ros2_control's mock GenericSystem): commands come back as readings, so a
// controller or a node can be tried with no simulator and no robot. Time is given by the owner.
#pragma once

#include <string>

#include "macsim/robot/kurt3d_description.h"
#include "macsim/robot/robot_interface.h"

namespace macsim::robot {

/// Odometry integrates the commanded twist (wheel speeds through the track width); the crane's
/// joints, the magnet and the rotunit speed mirror their commands; range readings stay as set.
class MockRobot : public RobotInterface {
 public:
  /// `track`: m between the wheel sides; commands time out after `command_timeout` s (the
  /// KURT3D's by default).
  MockRobot(std::string name, Capabilities capabilities, double track = kurt3d::kAxisLength,
            double command_timeout = kurt3d::kCommandTimeout);

  /// Moves the mock's clock to `now` (s), integrating odometry and the rotunit since the last.
  void advance(double now);
  /// What the range sensors report from now on.
  void set_ranges(std::vector<Range> ranges) { ranges_ = std::move(ranges); }

  std::string name() const override { return name_; }
  Capabilities capabilities() const override { return capabilities_; }
  /// Drive commands always; the rotunit's, the crane's and the magnet's if it has them.
  bool execute(const RobotCommand& command) override;
  Readings read() override;

 private:
  void drive(double linear, double angular);
  std::string name_;
  Capabilities capabilities_;
  double track_, command_timeout_;
  double now_ = 0, last_command_ = -1e300;
  double linear_ = 0, angular_ = 0;
  bool moved_ = false;
  Odometry odometry_;
  Rotunit rotunit_;
  Crane crane_;
  std::vector<Range> ranges_;
};

}  // namespace macsim::robot
