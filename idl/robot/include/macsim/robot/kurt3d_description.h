// The KURT3D's description, in one place: its dimensions, drive, sensor and camera mounts and the
// crane's geometry and limits (base_link: x forward, y left, z up; SI units). The simulator builds
// its model from it, the robot node publishes its mounts on tf_static and its text on
// rt/<robot>/robot_description, and controllers read it here or from tf_static. No DDS, no ODE.
// Sources: uos/kurt_driver (URDF, kurt.h, kurt_base) where documented; ours where not (the MACS
// KURT3D's crane, cameras and rotating laser are not documented; see sim_core/README.md).
#pragma once

#include <array>
#include <cmath>
#include <string>

namespace macsim::robot::kurt3d {

// ---- body and drive ------------------------------------------------------------------------
inline constexpr double kBaseMass = 15.6;                                   ///< kg, URDF base_link
inline constexpr std::array<double, 3> kBaseInertia{0.1185, 0.1928, 0.2402};  ///< kg m^2, URDF
inline constexpr std::array<double, 3> kBaseSize{0.43, 0.325, 0.215};  ///< m, URDF collision box
inline constexpr double kComBelowBaseLink = 0.0404;       ///< m, URDF CoM z = -0.0404
inline constexpr double kBaseLinkAboveWheelAxle = 0.107;  ///< m, URDF wheel joints
inline constexpr double kWheelX = 0.14;                   ///< m, front/rear axle from centre
inline constexpr double kWheelY = 0.14;                   ///< m, half track
inline constexpr double kWheelWidth = 0.035;              ///< m, indoor URDF
inline constexpr double kWheelPerimeter = 0.379;          ///< m, kurt_base `wheel_perimeter`
inline constexpr double kAxisLength = 0.28;               ///< m, kurt_base `axis_length`
inline constexpr double kTurningAdaptation = 0.69;        ///< kurt_base `turning_adaptation`
inline constexpr int kTicksPerTurn = 21950;               ///< kurt_base `ticks_per_turn_of_wheel`
inline constexpr double kCommandTimeout = 0.6;            ///< s without cmd_vel: zero speed
/// m, the wheels' radius.
inline constexpr double kWheelRadius = kWheelPerimeter / (2 * M_PI);
/// m, base_link above the floor (base_footprint): the axles' height plus the offset.
inline constexpr double kBaseHeight = kBaseLinkAboveWheelAxle + kWheelRadius;
/// m, half the robot's width with its wheels.
inline constexpr double kHalfWidth = 0.22;
/// m, base_link to the front bumper.
inline constexpr double kFront = 0.26;

// ---- the eight IR/sonar sensors (kurt_driver's infrared_sonar.urdf.xacro, kurt.h) ----------
/// One distance sensor in base_link (z = 0).
struct RangeSensor {
  const char* frame;     ///< e.g. "ir_left_front", "ultrasound_front"
  double x, y, yaw;      ///< m, m, rad
  bool sonar;            ///< ultrasound (Baumer) or infrared (Sharp GP2D12)
  double min_range;      ///< m
  double max_range;      ///< m
  double field_of_view;  ///< rad, full cone angle
};
inline constexpr double kIrFieldOfView = 0.07486, kSonarFieldOfView = 0.17809;
/// In the driver's order of frames.
inline constexpr std::array<RangeSensor, 8> kRangeSensors{{
    {"ultrasound_front", 0.217, 0.0, 0.0, true, 0.10, 1.00, kSonarFieldOfView},
    {"ir_left_front", 0.203, 0.153, M_PI / 4, false, 0.10, 0.80, kIrFieldOfView},
    {"ir_left", 0.0, 0.165, M_PI / 2, false, 0.10, 0.80, kIrFieldOfView},
    {"ir_left_back", -0.203, 0.153, 3 * M_PI / 4, false, 0.10, 0.80, kIrFieldOfView},
    {"ir_back", -0.217, 0.0, M_PI, false, 0.10, 0.80, kIrFieldOfView},
    {"ir_right_back", -0.203, -0.153, 5 * M_PI / 4, false, 0.10, 0.80, kIrFieldOfView},
    {"ir_right", 0.0, -0.165, 3 * M_PI / 2, false, 0.10, 0.80, kIrFieldOfView},
    {"ir_right_front", 0.203, -0.153, 7 * M_PI / 4, false, 0.10, 0.80, kIrFieldOfView},
}};

// ---- the stereo cameras (ours) -------------------------------------------------------------
/// The left optical centre; the right one mirrors it in y. Both look ahead, pitched down.
inline constexpr std::array<double, 3> kLeftCamera{0.05, 0.06, 0.42};
inline constexpr double kCameraPitch = 15 * M_PI / 180;  ///< rad, down over the crane

// ---- the laser scanner (SICK LMS200) -------------------------------------------------------
/// The scan origin on the rotating unit (KURT3D), and fixed at the front (KURT2).
inline constexpr std::array<double, 3> kRotatingLaser{-0.10, 0.0, 0.35};
inline constexpr std::array<double, 3> kFixedLaser{0.145, 0.0, 0.11};
inline constexpr double kLaserRate = 75.0;  ///< Hz, sweeps
inline constexpr int kRotunitTicks = 10240;  ///< encoder ticks per turn of the rotating unit

// ---- the crane and its magnet (ours) ------------------------------------------------------
inline constexpr double kPivotX = 0.05;       ///< m, the slew axis ahead of base_link
inline constexpr double kPivotHeight = 0.16;  ///< m, the lift pivot above base_link
inline constexpr double kBoomLength = 0.5;    ///< m, pivot to boom tip
inline constexpr double kLiftMin = -0.6, kLiftMax = 0.8;  ///< rad, the boom's stops
inline constexpr double kMaxHoist = 0.32;                 ///< m the magnet can be lowered
inline constexpr double kMagnetHeight = 0.03;             ///< m
inline constexpr double kMagnetRadius = 0.035;            ///< m
/// m, the boom's tip to the magnet's face with the hoist up.
inline constexpr double kMagnetBelowTip = 0.02 + kMagnetHeight;

/// The description as text (what rt/<robot>/robot_description carries): one `name value` line
/// per number above, `range_sensor frame x y yaw sonar min max fov` per sensor.
std::string description_text();

}  // namespace macsim::robot::kurt3d
