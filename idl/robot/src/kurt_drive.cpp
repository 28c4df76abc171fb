#include "macsim/robot/kurt_drive.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace macsim {

namespace {
// The rotating unit's encoder ticks per turn.
constexpr double kTicks = robot::kurt3d::kRotunitTicks;
}  // namespace

double KurtDriveParams::wheel_radius() const { return wheel_perimeter / (2.0 * M_PI); }

WheelSpeeds wheel_speeds_from_twist(double linear, double angular, const KurtDriveParams& params) {
  // The real driver uses the full axis length here (not half of it, as a textbook
  // differential drive would): controllers tuned on the robot expect this factor.
  return {linear - params.axis_length * angular, linear + params.axis_length * angular};
}

int speed_cm(double speed) {
  // The driver sends (int)(speed * 100): truncation towards zero. NaN is no speed.
  if (std::isnan(speed)) return 0;
  return static_cast<int>(std::clamp(std::trunc(speed * 100.0), -32768.0, 32767.0));
}

WheelSpeeds quantize_to_speed_cm(WheelSpeeds speeds) {
  return {speed_cm(speeds.left) / 100.0, speed_cm(speeds.right) / 100.0};
}

int16_t EncoderCounter::ticks_since_last(double angle) {
  const auto total = static_cast<int64_t>(std::floor(angle / (2.0 * M_PI) * ticks_per_turn_));
  const int64_t delta = total - last_total_;
  last_total_ = total;
  return static_cast<int16_t>(std::clamp<int64_t>(delta, std::numeric_limits<int16_t>::min(),
                                                  std::numeric_limits<int16_t>::max()));
}

void EncoderCounter::reset(double angle) {
  last_total_ = static_cast<int64_t>(std::floor(angle / (2.0 * M_PI) * ticks_per_turn_));
}

void KurtOdometry::integrate_frame(int left_ticks, int right_ticks) {
  const double dt = params_.frame_period;
  const double left = params_.wheel_perimeter * left_ticks / params_.ticks_per_turn;
  const double right = params_.wheel_perimeter * right_ticks / params_.ticks_per_turn;
  const double v_left = left / dt;
  const double v_right = right / dt;
  linear_ = (v_right + v_left) * 0.5;
  angular_ = (v_right - v_left) / params_.axis_length * params_.turning_adaptation;

  // Step in the driver's internal frame: z forward, x lateral, theta clockwise.
  constexpr double kEpsilon = 0.0001;
  double step_x = 0.0, step_z = 0.0, step_theta = 0.0;
  if (std::fabs(left - right) < kEpsilon) {
    if (std::fabs(left) >= kEpsilon) step_z = (left + right) * 0.5;
  } else {
    const double distance = 0.5 * (left + right);
    step_theta = (left - right) / params_.axis_length * params_.turning_adaptation;
    step_x = distance * std::sin(step_theta);
    step_z = distance * std::cos(step_theta);
  }
  internal_x_ += step_x * std::cos(internal_theta_) + step_z * std::sin(internal_theta_);
  internal_z_ += -step_x * std::sin(internal_theta_) + step_z * std::cos(internal_theta_);
  internal_theta_ += step_theta;
  if (internal_theta_ > M_PI) internal_theta_ -= 2.0 * M_PI;
  if (internal_theta_ < -M_PI) internal_theta_ += 2.0 * M_PI;
}

PlanarOdometry KurtOdometry::estimate() const {
  return {internal_z_, -internal_x_, -internal_theta_, linear_, angular_};
}

void KurtOdometry::reset() { *this = KurtOdometry(params_); }

double ir_range_from_raw(int raw) {
  if (raw < 100 || raw > 800) return kInvalidRange;
  // The driver keeps whole centimetres: (int)((30000 / (raw - 10))^(1/1.4) - 10).
  const int cm = static_cast<int>(std::pow(30000.0 / (raw - 10.0), 1.0 / 1.4) - 10.0);
  return cm / 100.0;
}

int ir_raw_from_range(double range) {
  const double cm = range * 100.0;
  return static_cast<int>(std::lround(30000.0 / std::pow(cm + 10.0, 1.4) + 10.0));
}

double sonar_range_from_raw(int raw) {
  if (raw < 100 || raw > 1000) return kInvalidRange;
  const int cm = static_cast<int>(0.110652 * raw + 11.9231);
  return cm / 100.0;
}

int sonar_raw_from_range(double range) {
  return static_cast<int>(std::lround((range * 100.0 - 11.9231) / 0.110652));
}

int rotunit_speed_command(double speed) {
  // The command is an int16 on the bus: saturate (about +-402 rad/s) instead of wrapping.
  if (std::isnan(speed)) return 0;
  return static_cast<int>(std::clamp(speed / (2.0 * M_PI) * kTicks / 20, -32768.0, 32767.0));
}

double rotunit_speed_from_command(int command) { return command * 2.0 * M_PI * 20 / kTicks; }

double rotunit_angle_from_ticks(int ticks) { return ticks * 2.0 * M_PI / kTicks; }

}  // namespace macsim
