// What the simulated KURT3D senses and carries: IR/sonar ranges, gyro and tilt, the laser
// scanner on its rotating unit, and the crane with its magnet.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "macsim/robot/kurt3d_description.h"

namespace macsim {

/// Height of base_link above the wheel axles, m (the KURT3D's description).
inline constexpr double kBaseLinkAboveWheelAxle = robot::kurt3d::kBaseLinkAboveWheelAxle;

/// One of the KURT's eight distance sensors, in base_link (the KURT3D's description).
using RangeSensorSpec = robot::kurt3d::RangeSensor;

/// The eight sensors of the real robot, in its driver's order of frames.
inline const std::array<RangeSensorSpec, 8>& kurt_range_sensors() {
  return robot::kurt3d::kRangeSensors;
}

/// One distance reading: metres, or kInvalidRange (-0.01) as the real driver reports it.
struct RangeReading {
  const RangeSensorSpec* sensor = nullptr;
  double range = -0.01;
};

/// Gyro and tilt: what the KURT's IMU topic and tilt sensor give.
struct ImuReading {
  double yaw = 0.0;           ///< rad, counter-clockwise, relative to the start, in (-pi, pi]
  double yaw_rate = 0.0;      ///< rad/s
  double roll = 0.0;          ///< rad, from the tilt sensor
  double pitch = 0.0;         ///< rad
  double yaw_variance = 0.0;  ///< rad^2
};

/// One sweep of the SICK LMS200: 181 beams over 180 degrees.
struct LaserScan {
  double stamp = 0.0;            ///< sim time of the sweep, s
  double angle_min = 0.0;        ///< rad, first beam
  double angle_increment = 0.0;  ///< rad between beams
  double range_min = 0.08, range_max = 10.0;
  std::vector<float> ranges;   ///< m; +inf where nothing was hit within range_max
  double rotunit_angle = 0.0;  ///< rad, the rotating unit's angle during the sweep
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< scanner origin in base_link
};

/// A 3D point cloud in base_link, assembled from the sweeps of one rotunit revolution.
struct PointCloud {
  double stamp = 0.0;
  std::vector<Eigen::Vector3f> points;
};

/// Joint targets of the crane: slew about the vertical (rad, + counter-clockwise), boom lift
/// (rad, + raises the tip) and hoist (m the magnet hangs below the boom tip).
struct CraneCommand {
  double slew = 0.0;
  double lift = 0.0;
  double hoist = 0.0;
};

/// The crane as it is.
struct CraneState {
  double slew = 0.0, lift = 0.0, hoist = 0.0;  ///< measured joint positions
  bool magnet_on = false;
  std::string held_object;  ///< name of the object on the magnet, or empty
};

}  // namespace macsim
