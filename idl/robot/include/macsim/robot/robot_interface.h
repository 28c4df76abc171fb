// One robot interface (ros2_control's rule): commands in, readings out, with the simulated
// KURT, the real KURT over CAN and a mock behind it. No DDS here: RobotNode serves any of them
// on rt/<robot>/*, so the simulator and the real robot's adapter cannot drift apart.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "macsim/robot/robot_command.h"

namespace macsim::robot {

/// What a robot has besides its drive, odometry and wheel joints; the node serves the topics
/// of what it has, and names those of what it lacks.
struct Capabilities {
  bool ground_truth = false;    ///< where the robot really is (a simulator knows)
  bool ranges = false;          ///< the eight IR/sonar sensors
  bool imu = false;             ///< gyro yaw and tilt
  bool rotunit = false;         ///< the rotating laser unit: rot_vel in, laser_rot_joint out
  bool laser = false;           ///< laser scans
  bool laser_rotating = false;  ///< the scanner turns with the rotunit (scan360, not scan)
  bool points = false;          ///< a 3D cloud per rotunit revolution
  bool crane = false;           ///< crane joint commands and state
  bool magnet = false;          ///< the magnet switch
  /// A plug-in's own command types (robot_command.h) by name, each served on
  /// rt/<robot>/command/<name> as std_msgs/Float64MultiArray (its numbers in `data`).
  std::vector<std::string> commands;
};

/// Odometry as the driver computes it (REP-103, odometry frame) and the wheel angles.
struct Odometry {
  double x = 0, y = 0, yaw = 0;  ///< m, m, rad
  double linear = 0;             ///< m/s
  double angular = 0;            ///< rad/s
  double left_wheel = 0;         ///< rad, wrapped to (-pi, pi]
  double right_wheel = 0;
};

/// Where base_footprint really is (world frame) and how it moves (robot frame).
struct GroundTruth {
  std::array<double, 3> position{};
  std::array<double, 4> orientation{0, 0, 0, 1};  ///< x, y, z, w
  std::array<double, 3> linear{};                 ///< m/s
  std::array<double, 3> angular{};                ///< rad/s
};

/// One distance reading.
struct Range {
  std::string frame;  ///< e.g. "ir_left_front", "ultrasound_front"
  bool sonar = false;
  double range = 0;  ///< m, or -0.01 when invalid (as the real driver reports)
};

/// Gyro and tilt.
struct Imu {
  double roll = 0, pitch = 0, yaw = 0;  ///< rad
  double yaw_variance = 0;              ///< rad^2
  double yaw_rate = 0;                  ///< rad/s
};

/// One laser sweep.
struct Scan {
  std::string frame;  ///< "laser360" on the rotunit, "laser" when fixed
  double angle_min = 0, angle_increment = 0;
  double range_min = 0, range_max = 0;
  double scan_time = 0;       ///< s between sweeps
  std::vector<float> ranges;  ///< m; +inf where nothing was hit
};

/// The rotating unit as its encoder reports it.
struct Rotunit {
  double angle = 0;  ///< rad
  double speed = 0;  ///< rad/s, as commanded (quantized)
};

/// A 3D cloud in base_link: x, y, z of each point.
struct Cloud {
  std::vector<float> xyz;
};

/// The crane's joints and magnet.
struct Crane {
  double slew = 0, lift = 0, hoist = 0;  ///< rad, rad, m
  bool magnet_on = false;
  std::string held_object;  ///< empty when it holds nothing (or cannot tell)
};

/// A fixed transform from one of the robot's frames to another (published on tf_static).
struct Mount {
  std::string parent, child;
  std::array<double, 3> position{};               ///< m, in the parent frame
  std::array<double, 4> orientation{0, 0, 0, 1};  ///< x, y, z, w
};

/// The robot's frames (REP-105: base_footprint on the floor, base_link in the body): the fixed
/// mounts, and where the moving parts turn, for the transforms the node publishes live.
struct Frames {
  std::vector<Mount> mounts;  ///< base_footprint -> base_link, sensors, cameras
  /// The laser's frame at rotunit angle 0 (its scan plane is the frame's xy plane); the rotunit
  /// turns it about base_link's z axis. Empty child: no rotating laser.
  Mount laser;
  /// base_link -> crane_turret at the slew axis (turns about z by slew), -> crane_boom (turns
  /// about -y by lift), -> crane_magnet at the boom tip, lowered by hoist. Empty: no crane.
  Mount crane_pivot;
  double boom_length = 0;  ///< m, pivot to tip
  /// The robot's description as text (rt/<robot>/robot_description); empty: none.
  std::string description;
};

/// What is new since the last read(); absent (or empty) what is not.
struct Readings {
  double stamp = 0;  ///< s: sim time in a simulator, wall time on the robot
  std::optional<Odometry> odometry;
  std::optional<GroundTruth> ground_truth;
  std::vector<Range> ranges;
  std::optional<Imu> imu;
  std::optional<Scan> scan;
  std::optional<Rotunit> rotunit;
  std::optional<Cloud> cloud;
  std::optional<Crane> crane;
};

/// A robot: commands and read() on its owner's thread only.
class RobotInterface {
 public:
  virtual ~RobotInterface() = default;
  /// The namespace of its topics, e.g. "kurt".
  virtual std::string name() const = 0;
  virtual Capabilities capabilities() const = 0;
  /// Carries out a command (robot_command.h); false, doing nothing, for one it does not have.
  virtual bool execute(const RobotCommand& command) = 0;
  /// The readings new since the last call.
  virtual Readings read() = 0;
  /// The robot's frames; none by default.
  virtual Frames frames() const { return {}; }
};

}  // namespace macsim::robot
