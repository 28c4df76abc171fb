// The KURT3D's rigid bodies and joints as plain numbers (chassis, six wheels, crane), taken from
// sim_core's KurtConfig, so the hand-built ODE and MuJoCo baselines build the robot sim_core
// builds: same masses, sizes, anchors, axes, stops and motor limits.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world_spec.h"

namespace macsim::bench {

/// One rigid part: a body at `pose` (its centre of mass) with one collision shape.
struct VehiclePart {
  const char* name;
  Pose pose;                         ///< of the body (its centre of mass), world frame
  double mass = 0.0;                 ///< kg
  Eigen::Vector3d inertia{0, 0, 0};  ///< diagonal about the centre of mass; zero: from the shape
  ComponentSpec shape;               ///< relative to the body's pose
};

/// A motorised joint between two parts (child, parent); velocity set-point held by a force limit.
struct VehicleJoint {
  int child = 0, parent = 0;                       ///< indices into VehicleLayout::parts
  bool slider = false;                             ///< hinge otherwise
  Eigen::Vector3d anchor{0, 0, 0}, axis{0, 0, 1};  ///< world frame
  double lo = -INFINITY, hi = INFINITY;            ///< stops (rad or m)
  double max_force = 0.0;                          ///< N m or N
};

/// The robot placed at a base_footprint pose: parts[0] is the chassis, parts[1..6] the wheels
/// (left front, middle, rear, then right), then turret, boom and magnet.
struct VehicleLayout {
  std::vector<VehiclePart> parts;
  std::vector<VehicleJoint> joints;  ///< joints[0..5] are the wheel motors
  double wheel_radius = 0.0;
  double wheel_friction = 1.0;
};

/// The layout of a robot of `config` standing with base_footprint at `footprint`.
inline VehicleLayout vehicle_layout(const KurtConfig& config, const Pose& footprint) {
  const KurtBodyParams& b = config.body;
  const CraneParams& c = config.crane_params;
  constexpr double kMagnetHeight = 0.03;  // as sim_core's magnet
  VehicleLayout out;
  out.wheel_radius = config.drive.wheel_radius();
  out.wheel_friction = b.wheel_friction;
  const Eigen::Quaterniond q = footprint.orientation;
  const Eigen::Vector3d base_link =
      footprint.position +
      q * Eigen::Vector3d(0, 0, b.wheel_axle_below_base_link + out.wheel_radius);
  auto at = [&](double x, double y, double z) -> Pose {
    return {base_link + q * Eigen::Vector3d(x, y, z), q};
  };
  auto shape = [](Shape s, Eigen::Vector3d size, Pose offset = {}) {
    ComponentSpec comp;
    comp.shape = s;
    comp.size = size;
    comp.pose = offset;
    return comp;
  };
  // Chassis: the body at its centre of mass, the box centred on base_link.
  out.parts.push_back(
      {"chassis", at(0, 0, -b.com_below_base_link), b.base_mass, b.base_inertia,
       shape(Shape::Box, b.base_size, Pose{Eigen::Vector3d(0, 0, b.com_below_base_link)})});
  const double xs[3] = {b.wheel_x, 0.0, -b.wheel_x};
  const Eigen::Quaterniond across(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  for (int i = 0; i < 6; ++i) {
    const Pose centre =
        at(xs[i % 3], i < 3 ? b.wheel_y : -b.wheel_y, -b.wheel_axle_below_base_link);
    out.parts.push_back({"wheel",
                         centre,
                         b.wheel_mass,
                         {0, 0, 0},
                         shape(Shape::Cylinder, {out.wheel_radius, 0, b.wheel_width},
                               Pose{Eigen::Vector3d::Zero(), across})});
    out.joints.push_back({i + 1, 0, false, centre.position, q * Eigen::Vector3d::UnitY(), -INFINITY,
                          INFINITY, b.wheel_torque});
  }
  if (!config.crane) return out;
  const double box_top = b.base_size.z() / 2;
  const double turret_height = c.pivot_height - box_top;
  out.parts.push_back({"turret",
                       at(c.pivot_x, 0, box_top + turret_height / 2),
                       1.0,
                       {0, 0, 0},
                       shape(Shape::Cylinder, {0.05, 0, turret_height})});
  out.parts.push_back({"boom",
                       at(c.pivot_x + c.boom_length / 2, 0, c.pivot_height),
                       0.5,
                       {0, 0, 0},
                       shape(Shape::Box, {c.boom_length, 0.04, 0.04})});
  out.parts.push_back({"magnet",
                       at(c.pivot_x + c.boom_length, 0, c.pivot_height - 0.02 - kMagnetHeight / 2),
                       c.magnet_mass,
                       {0, 0, 0},
                       shape(Shape::Cylinder, {c.magnet_radius, 0, kMagnetHeight})});
  const int turret = 7, boom = 8, magnet = 9;
  out.joints.push_back({turret, 0, false, at(c.pivot_x, 0, box_top).position,
                        q * Eigen::Vector3d::UnitZ(), -INFINITY, INFINITY, c.slew_torque});
  out.joints.push_back({boom, turret, false, at(c.pivot_x, 0, c.pivot_height).position,
                        q * -Eigen::Vector3d::UnitY(), -0.6, 0.8, c.lift_torque});
  out.joints.push_back({magnet, boom, true,
                        at(c.pivot_x + c.boom_length, 0, c.pivot_height).position,
                        q * -Eigen::Vector3d::UnitZ(), 0.0, c.max_hoist, c.hoist_force});
  return out;
}

}  // namespace macsim::bench
