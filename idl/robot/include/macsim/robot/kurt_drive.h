// KURT3D drive kinematics as the real robot's driver (uos/kurt_driver) computes them:
// twist -> wheel speeds, SPEED_CM quantization, encoder ticks and odometry. No ODE, no DDS:
// the simulated robot and the real-robot adapter share this code.
#pragma once

#include <cstdint>

#include "macsim/robot/kurt3d_description.h"

namespace macsim {

/// Drive parameters of the KURT3D; defaults from its description (the real driver's indoor values).
struct KurtDriveParams {
  double wheel_perimeter = robot::kurt3d::kWheelPerimeter;    ///< m, kurt_base default `wheel_perimeter`
  double axis_length = robot::kurt3d::kAxisLength;         ///< m, track used by cmd_vel and odometry (`axis_length`)
  double turning_adaptation = robot::kurt3d::kTurningAdaptation;  ///< skid-slip factor of the odometry (`turning_adaptation`)
  int ticks_per_turn = robot::kurt3d::kTicksPerTurn;        ///< encoder ticks per wheel turn (`ticks_per_turn_of_wheel`)
  double frame_period = 0.01;        ///< s, one ENCODER CAN frame every 10 ms (fixed in odometry)
  double command_timeout = robot::kurt3d::kCommandTimeout;      ///< s without cmd_vel before the driver commands zero speed

  /// Wheel radius in m (perimeter / 2 pi).
  double wheel_radius() const;
};

/// Left and right wheel rim speeds in m/s.
struct WheelSpeeds {
  double left = 0.0;
  double right = 0.0;
};

/// cmd_vel to wheel speeds as the real driver maps it: v -+ axis_length * omega (full track).
WheelSpeeds wheel_speeds_from_twist(double linear, double angular, const KurtDriveParams& params);

/// A speed as the driver puts it in a SPEED_CM frame: whole cm/s, truncated towards zero,
/// saturated to the frame's int16.
int speed_cm(double speed);
/// Speeds as the microcontroller receives them in SPEED_CM mode (speed_cm(), back in m/s).
WheelSpeeds quantize_to_speed_cm(WheelSpeeds speeds);

/// Turns a continuous wheel angle into the per-frame tick deltas of the KURT's ENCODER frame.
class EncoderCounter {
 public:
  explicit EncoderCounter(int ticks_per_turn = KurtDriveParams{}.ticks_per_turn)
      : ticks_per_turn_(ticks_per_turn) {}
  /// Ticks since the previous call for a wheel now at `angle` rad (continuous, not wrapped),
  /// saturated to the frame's int16 range.
  int16_t ticks_since_last(double angle);
  /// Restarts counting from `angle` without producing ticks.
  void reset(double angle);
  /// Visits the fields that change, for saving, restoring and hashing a state.
  template <class Archive>
  void fields(Archive& ar) {
    ar(ticks_per_turn_, last_total_);
  }

 private:
  int ticks_per_turn_;
  int64_t last_total_ = 0;
};

/// Planar pose and velocity of the robot in the odometry frame (REP-103: x forward, y left,
/// yaw counter-clockwise), as the real driver publishes it.
struct PlanarOdometry {
  double x = 0.0, y = 0.0, yaw = 0.0;  ///< m, m, rad in (-pi, pi]
  double linear = 0.0;                 ///< m/s along x of the robot
  double angular = 0.0;                ///< rad/s about z
};

/// Dead reckoning from ENCODER frames, bit for bit as kurt_driver's Kurt::odometry():
/// fixed 10 ms frame period, turning adaptation, internal frame z forward / x right /
/// theta clockwise, published as x = z, y = -x, yaw = -theta.
class KurtOdometry {
 public:
  explicit KurtOdometry(const KurtDriveParams& params = {}) : params_(params) {}
  /// Integrates one ENCODER frame (ticks of the left and right side since the previous frame).
  void integrate_frame(int left_ticks, int right_ticks);
  /// The current estimate in REP-103 convention.
  PlanarOdometry estimate() const;
  void reset();
  /// Visits the fields that change, for saving, restoring and hashing a state.
  template <class Archive>
  void fields(Archive& ar) {
    ar(params_.wheel_perimeter, params_.axis_length, params_.turning_adaptation,
       params_.ticks_per_turn, params_.frame_period, params_.command_timeout, internal_x_,
       internal_z_, internal_theta_, linear_, angular_);
  }

 private:
  KurtDriveParams params_;
  double internal_x_ = 0.0, internal_z_ = 0.0, internal_theta_ = 0.0;
  double linear_ = 0.0, angular_ = 0.0;
};

/// A range reading the real driver reports as invalid (kurt_base publishes -1 cm).
inline constexpr double kInvalidRange = -0.01;

/// IR range (m) from a Sharp GP2D12 ADC value, as the driver converts it; kInvalidRange
/// outside raw 100..800.
double ir_range_from_raw(int raw);
/// The ADC value the IR sensor gives at a distance (m), the inverse of ir_range_from_raw.
int ir_raw_from_range(double range);
/// Ultrasound range (m) from an ADC value, as the driver converts it; kInvalidRange outside
/// raw 100..1000.
double sonar_range_from_raw(int raw);
/// The ADC value the ultrasound sensor gives at a distance (m).
int sonar_raw_from_range(double range);

/// Rotunit speed command as the driver sends it: speed / 2 pi * kRotunitTicks / 20, truncated, saturated
/// to int16.
int rotunit_speed_command(double speed);
/// The speed (rad/s) a rotunit command value means: value * 2 pi * 20 / kRotunitTicks.
double rotunit_speed_from_command(int command);
/// Rotunit angle (rad) from its encoder value: ticks * 2 pi / kRotunitTicks (the description's ticks per turn).
double rotunit_angle_from_ticks(int ticks);

}  // namespace macsim
