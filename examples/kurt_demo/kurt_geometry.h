// Where the KURT3D's sensors and crane sit (base_link: x forward, y left, z up; base_link is
// above the floor by base_height). What a robot description (URDF) would give a controller.
#pragma once

#include <cmath>

namespace kurt_demo {

struct KurtGeometry {
  double base_height = 0.167;  ///< m, base_link above the floor (wheel radius + axle offset)
  // the left camera's optical centre, looking ahead and pitched down; the right one is
  // `baseline` to its right (the baseline itself comes with the camera calibration)
  double camera_x = 0.05, camera_y = 0.06, camera_z = 0.42;
  double camera_pitch = 15.0 * M_PI / 180.0;  ///< rad, down
  // the crane: the boom turns (slew) about the vertical through the pivot and lifts about y
  double pivot_x = 0.05, pivot_z = 0.16;
  double boom_length = 0.5;
  double lift_min = -0.6, lift_max = 0.8;  ///< rad
  double max_hoist = 0.32;                 ///< m
  double magnet_below_tip = 0.05;          ///< m, the boom's tip to the magnet's face
  // the laser scanner's origin on the rotating unit
  double laser_z = 0.35;
  double half_width = 0.22;  ///< m, half the robot's width with its wheels
  double front = 0.26;       ///< m, base_link to the front bumper
};

}  // namespace kurt_demo
