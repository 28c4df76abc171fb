// What every robot model shares in making its readings and frames for the robot node.
#pragma once

#include <random>
#include <string>

#include "macsim/sim_core/kurt_sensors.h"
#include "macsim/sim_core/robot_model.h"

namespace macsim::detail {

/// A fixed transform from `parent` to `child`.
robot::Mount robot_mount(const std::string& parent, const std::string& child,
                         const Eigen::Vector3d& position,
                         const Eigen::Quaterniond& orientation = Eigen::Quaterniond::Identity());
/// The stereo pair's camera frames on base_link and their optical frames (z ahead, x right,
/// y down: REP-103).
void add_stereo_frames(const StereoMount& cameras, robot::Frames& frames);
/// Odometry as the node serves it: the estimate and the wheels' angles wrapped to (-pi, pi].
robot::Odometry odometry_reading(const PlanarOdometry& odometry, double left_wheel,
                                 double right_wheel);
/// Where the robot's base_footprint is (world) and how it moves (robot frame).
robot::GroundTruth ground_truth_reading(const RobotModel& robot);
/// A box, sphere or cylinder geom where it is now, in `color`, for drawing.
ShapeView shape_view(dxGeom* geom, const Color& color);
/// A sweep's range noise, N(0, sigma) (none if sigma <= 0). Made anew for each sweep: its one
/// distribution uses both numbers of each pair it draws, and keeps nothing past the sweep, so
/// that the generator alone stays the noise's state.
class SweepNoise {
 public:
  SweepNoise(std::mt19937& rng, double sigma) : rng_(rng), sigma_(sigma) {}
  /// The next beam's noise (m).
  double operator()() { return sigma_ > 0 ? sigma_ * normal_(rng_) : 0.0; }

 private:
  std::mt19937& rng_;
  double sigma_;
  std::normal_distribution<double> normal_;
};
/// A sweep as the node serves it.
robot::Scan scan_reading(const LaserScan& scan, const std::string& frame, double scan_time);

}  // namespace macsim::detail

namespace macsim {

// The field lists (archive(), state_archive.h) of what robot models keep in their state.
template <class Ar>
void archive(Ar& ar, WheelSpeeds& w) {
  ar(w.left, w.right);
}
template <class Ar>
void archive(Ar& ar, PlanarOdometry& o) {
  ar(o.x, o.y, o.yaw, o.linear, o.angular);
}
template <class Ar>
void archive(Ar& ar, LaserScan& s) {
  ar(s.stamp, s.angle_min, s.angle_increment, s.range_min, s.range_max, s.ranges, s.rotunit_angle,
     s.origin);
}

}  // namespace macsim
