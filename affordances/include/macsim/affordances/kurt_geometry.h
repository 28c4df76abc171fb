// Where the KURT3D's sensors and crane sit (base_link: x forward, y left, z up; base_link is
// above the floor by base_height), taken from the robot's one description
// (macsim/robot/kurt3d_description.h, which macsim also publishes on rt/kurt/robot_description).
#pragma once

#include "macsim/robot/kurt3d_description.h"

namespace macsim::affordances {

namespace description = macsim::robot::kurt3d;

struct KurtGeometry {
  double base_height = description::kBaseHeight;  ///< m, base_link above the floor
  // the left camera's optical centre, looking ahead and pitched down; the right one is
  // `baseline` to its right (the baseline itself comes with the camera calibration)
  double camera_x = description::kLeftCamera[0], camera_y = description::kLeftCamera[1],
         camera_z = description::kLeftCamera[2];
  double camera_pitch = description::kCameraPitch;  ///< rad, down
  // the crane: the boom turns (slew) about the vertical through the pivot and lifts about y
  double pivot_x = description::kPivotX, pivot_z = description::kPivotHeight;
  double boom_length = description::kBoomLength;
  double lift_min = description::kLiftMin, lift_max = description::kLiftMax;  ///< rad
  double max_hoist = description::kMaxHoist;                                 ///< m
  double magnet_below_tip = description::kMagnetBelowTip;  ///< m, the boom's tip to the magnet's face
  // the laser scanner's origin on the rotating unit
  double laser_z = description::kRotatingLaser[2];
  double half_width = description::kHalfWidth;  ///< m, half the robot's width with its wheels
  double front = description::kFront;           ///< m, base_link to the front bumper
};

}  // namespace macsim::affordances
