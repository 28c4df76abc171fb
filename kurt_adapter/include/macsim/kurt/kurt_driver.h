// The host side of the KURT's driver without DDS: commands in, CAN frames out every 10 ms,
// the microcontroller's frames in, robot state out, as uos/kurt_driver computes it.
#pragma once

#include <array>
#include <optional>

#include "macsim/kurt/kurt_can.h"
#include "macsim/robot/kurt_drive.h"

namespace macsim::kurt {

/// What a received frame updated.
enum class Update { None, Odometry, Ranges, Imu, Tilt, Rotunit };

/// Driver state machine; call from one thread. Times are seconds of a monotonic clock.
class KurtDriver {
 public:
  explicit KurtDriver(const KurtDriveParams& params = {}) : params_(params), odometry_(params) {}
  /// The drive's parameters (wheel size, axis length, encoder ticks).
  const KurtDriveParams& params() const { return params_; }

  /// A cmd_vel: wheel speeds v -+ axis_length * omega, held until the command timeout. A
  /// command with a number that is not finite is ignored (as RobotNode drops it).
  void command_twist(double linear, double angular, double now);
  /// Wheel rim speeds (m/s), held until the command timeout.
  void command_wheel_speeds(WheelSpeeds speeds, double now);
  /// The SPEED_CM frame to send at `now` (every 10 ms): zero once the last command is older
  /// than the command timeout (0.6 s).
  CanFrame control_frame(double now) const;
  /// The SETROTUNIT frame for a rotunit speed (rad/s); remembers the speed as quantized.
  CanFrame command_rotunit(double speed);
  /// The rotunit's commanded speed (rad/s, quantized as the rotunit receives it).
  double rotunit_speed() const { return rotunit_speed_; }
  /// The wheel speeds control_frame() commands at `now`.
  WheelSpeeds commanded(double now) const;

  /// Integrates one frame from the microcontroller or the rotunit.
  Update handle(const CanFrame& frame);

  /// Odometry from the ENCODER frames (KurtOdometry: the driver's formulas).
  PlanarOdometry odometry() const { return odometry_.estimate(); }
  /// Accumulated wheel angle of the left (0) and right (1) side, rad, wrapped to +-pi.
  double wheel_angle(int side) const { return wheel_angle_[side]; }
  /// The eight ranges (m, kInvalidRange when invalid) in kRangeChannels' order.
  const std::array<double, 8>& ranges() const { return ranges_; }
  /// Gyro yaw (rad, +-pi) and variance, once the first 100 frames were dropped.
  std::optional<GyroReading> gyro() const { return gyro_; }
  std::optional<Tilt> tilt() const { return tilt_; }
  /// Rotunit angle (rad), once a GETROTUNIT frame came.
  std::optional<double> rotunit_angle() const { return rotunit_angle_; }
  uint64_t encoder_frames() const { return encoder_frames_; }

 private:
  KurtDriveParams params_;
  KurtOdometry odometry_;
  WheelSpeeds target_;
  double last_command_ = -1e300;
  std::array<double, 2> wheel_angle_{};
  std::array<int, 16> adc_{};
  std::array<double, 8> ranges_{};
  int gyro_frames_ = 0;
  std::optional<GyroReading> gyro_;
  std::optional<Tilt> tilt_;
  std::optional<double> rotunit_angle_;
  double rotunit_speed_ = 0.0;
  uint64_t encoder_frames_ = 0;
};

}  // namespace macsim::kurt
