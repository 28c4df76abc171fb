#include "macsim/kurt/kurt_driver.h"

#include <cmath>

namespace macsim::kurt {

void KurtDriver::command_twist(double linear, double angular, double now) {
  if (!std::isfinite(linear) || !std::isfinite(angular)) return;
  command_wheel_speeds(wheel_speeds_from_twist(linear, angular, params_), now);
}

void KurtDriver::command_wheel_speeds(WheelSpeeds speeds, double now) {
  if (!std::isfinite(speeds.left) || !std::isfinite(speeds.right) || !std::isfinite(now)) return;
  target_ = speeds;
  last_command_ = now;
}

WheelSpeeds KurtDriver::commanded(double now) const {
  return now - last_command_ > params_.command_timeout ? WheelSpeeds{} : target_;
}

CanFrame KurtDriver::control_frame(double now) const { return encode_speed_cm(commanded(now)); }

CanFrame KurtDriver::command_rotunit(double speed) {
  rotunit_speed_ = rotunit_speed_from_command(rotunit_speed_command(speed));
  return encode_rotunit_speed(speed);
}

Update KurtDriver::handle(const CanFrame& frame) {
  if (auto ticks = decode_encoder(frame)) {
    odometry_.integrate_frame(ticks->left, ticks->right);
    const int counts[2] = {ticks->left, ticks->right};
    for (int side = 0; side < 2; ++side) {
      wheel_angle_[side] = std::remainder(
          wheel_angle_[side] + 2.0 * M_PI * counts[side] / params_.ticks_per_turn, 2.0 * M_PI);
    }
    ++encoder_frames_;
    return Update::Odometry;
  }
  if (auto adc = decode_adc(frame)) {
    for (int i = 0; i < 4; ++i) adc_[adc->first_channel + i] = adc->raw[i];
    if (adc->first_channel != 8) return Update::None;  // the ranges are complete with ch 8..11
    for (std::size_t i = 0; i < kRangeChannels.size(); ++i) {
      const RangeChannel& c = kRangeChannels[i];
      ranges_[i] =
          c.sonar ? sonar_range_from_raw(adc_[c.channel]) : ir_range_from_raw(adc_[c.channel]);
    }
    return Update::Ranges;
  }
  if (auto gyro = decode_gyro(frame)) {
    // The driver drops the first 100 frames while the gyro settles. Its offset correction after
    // that never runs (a post-increment makes its `== 100` test unreachable), so the angle is
    // used as it comes, wrapped to +-pi.
    if (gyro_frames_ < 100) {
      ++gyro_frames_;
      return Update::None;
    }
    double yaw = gyro->yaw;
    if (yaw > M_PI) yaw -= 2.0 * M_PI;
    if (yaw < -M_PI) yaw += 2.0 * M_PI;
    gyro_ = GyroReading{yaw, gyro->variance};
    return Update::Imu;
  }
  if (auto tilt = decode_tilt(frame)) {
    // Outside +-1 g (no sensor fitted, a glitch) asin gives NaN: keep the last good reading.
    if (!std::isfinite(tilt->roll_deg) || !std::isfinite(tilt->pitch_deg)) return Update::None;
    tilt_ = tilt;
    return Update::Tilt;
  }
  if (auto ticks = decode_rotunit_angle(frame)) {
    rotunit_angle_ = rotunit_angle_from_ticks(*ticks);
    return Update::Rotunit;
  }
  return Update::None;
}

}  // namespace macsim::kurt
