// What the robot perceives of the object (or ramp) before it acts, from its own sensors: colour
// and apparent size from the stereo cameras, range, height and profile from the laser's
// vertical sweep straight ahead.
#pragma once

#include <optional>
#include <vector>

#include "macsim/client/robot_devices.h"

namespace affordances {

/// The perceived features a learner gets (SI units; pixels where it says so).
struct Percept {
  bool seen = false;           ///< the cameras found a coloured blob
  double r = 0, g = 0, b = 0;  ///< mean colour of the blob, [0, 1]
  double hue = 0;              ///< degrees, [0, 360)
  double area_px = 0;          ///< pixels of the blob in the left image
  double width_px = 0, height_px = 0;
  double fill = 0;          ///< area over its bounding box: 1 for a box face, 0.79 a disc
  double bearing = 0;       ///< rad, counter-clockwise from ahead (left camera)
  double stereo_range = 0;  ///< m along the optical axis, from the blob's disparity
  double width_m = 0;       ///< apparent width at that range, m
  bool laser_hit = false;   ///< the sweep hit something above the floor ahead
  double laser_range = 0;   ///< m ahead of base_link to the nearest hit above the floor
  double laser_height = 0;  ///< m above the floor of the highest hit
  double laser_depth = 0;   ///< m from the lowest to the highest hit, along x
  double laser_slope = 0;   ///< rad, from the lowest to the highest hit (ramps: the slope)
};

/// Where the sensors sit on the KURT3D (base_link: x ahead, y left, z up).
struct SensorMount {
  double base_height = 0.167;              ///< base_link above the floor, m
  double laser_x = -0.10, laser_z = 0.35;  ///< the scanner's origin on the rotating unit
};

/// Adds the cameras' view: the largest saturated blob of the left image, matched in the right.
void perceive_image(const macsim::client::StereoFrame& frame, Percept& percept);
/// Adds the laser's: one sweep of the scanner standing still, its plane straight ahead.
void perceive_scan(const macsim::client::Laser::Scan& scan, const SensorMount& mount,
                   Percept& percept);

/// The features a learner trains on, in a fixed order, and their names.
std::vector<double> features(const Percept& percept);
const std::vector<const char*>& feature_names();

}  // namespace affordances
