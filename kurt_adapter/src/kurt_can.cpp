#include "macsim/kurt/kurt_can.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace macsim::kurt {
namespace {

void put16(CanFrame& f, int at, uint16_t v) {
  f.data[at] = static_cast<uint8_t>(v >> 8);
  f.data[at + 1] = static_cast<uint8_t>(v & 0xFF);
}
void put32(CanFrame& f, int at, uint32_t v) {
  put16(f, at, static_cast<uint16_t>(v >> 16));
  put16(f, at + 2, static_cast<uint16_t>(v & 0xFFFF));
}
uint16_t get16(const CanFrame& f, int at) {
  return static_cast<uint16_t>((f.data[at] << 8) | f.data[at + 1]);
}
uint32_t get32(const CanFrame& f, int at) {
  return (static_cast<uint32_t>(get16(f, at)) << 16) | get16(f, at + 2);
}
CanFrame frame(uint32_t id) {
  CanFrame f;
  f.id = id;
  f.dlc = 8;
  return f;
}
CanFrame control(ControlMode mode) {
  CanFrame f = frame(can_id::kControl);
  put16(f, 0, static_cast<uint16_t>(mode));
  return f;
}
bool is(const CanFrame& f, uint32_t id, int min_length) {
  return f.id == id && f.dlc >= min_length;
}

}  // namespace

uint16_t omega_word(double omega, bool antiwindup) {
  const long o = std::lround(100.0 * omega / M_PI);
  return static_cast<uint16_t>(((std::labs(o) & 0x3FFF) << 2) | ((o < 0 ? 1 : 0) << 1) |
                               (antiwindup ? 1 : 0));
}

CanFrame encode_speed_cm(WheelSpeeds speeds, double omega, bool antiwindup) {
  CanFrame f = control(ControlMode::SpeedCm);
  put16(f, 2, static_cast<uint16_t>(speed_cm(speeds.left)));
  put16(f, 4, static_cast<uint16_t>(speed_cm(speeds.right)));
  put16(f, 6, omega_word(omega, antiwindup));
  return f;
}

CanFrame encode_hard_stop() {
  CanFrame f = control(ControlMode::Raw);
  f.data[2] = 0x01;  // direction 0 (forward) << 1 | brake
  put16(f, 3, 1023);
  f.data[5] = 0x01;
  put16(f, 6, 1023);
  return f;
}

CanFrame encode_actuator(bool on) {
  return control(on ? ControlMode::ActuatorOn : ControlMode::ActuatorOff);
}

CanFrame encode_rotunit_speed(double speed) {
  CanFrame f = frame(can_id::kRotunitSpeed);
  put16(f, 0, static_cast<uint16_t>(static_cast<int16_t>(rotunit_speed_command(speed))));
  return f;
}

std::optional<ControlCommand> decode_control(const CanFrame& f) {
  if (!is(f, can_id::kControl, 8)) return std::nullopt;
  ControlCommand c;
  const uint16_t mode = get16(f, 0);
  switch (mode) {
    case 0x0000:
      c.mode = ControlMode::Raw;
      c.hard_stop =
          (f.data[2] & 1) && (f.data[5] & 1) && get16(f, 3) == 1023 && get16(f, 6) == 1023;
      return c;
    case 0x0002:
      c.mode = ControlMode::SpeedCm;
      c.left_cm = static_cast<int16_t>(get16(f, 2));
      c.right_cm = static_cast<int16_t>(get16(f, 4));
      c.omega = get16(f, 6);
      return c;
    case 0x0001:
    case 0xFF00:
    case 0xFF01:
    case 0xFF02:
    case 0xFF03:
    case 0xFF04:
    case 0xFF05:
    case 0xFFFF:
      c.mode = static_cast<ControlMode>(mode);
      return c;
    default:
      return std::nullopt;
  }
}

std::optional<int> decode_rotunit_speed(const CanFrame& f) {
  if (!is(f, can_id::kRotunitSpeed, 2)) return std::nullopt;
  return static_cast<int16_t>(get16(f, 0));
}

std::optional<EncoderTicks> decode_encoder(const CanFrame& f) {
  if (!is(f, can_id::kEncoder, 4)) return std::nullopt;
  return EncoderTicks{static_cast<int16_t>(get16(f, 0)), static_cast<int16_t>(get16(f, 2))};
}

CanFrame encode_encoder(EncoderTicks ticks) {
  CanFrame f = frame(can_id::kEncoder);
  put16(f, 0, static_cast<uint16_t>(ticks.left));
  put16(f, 2, static_cast<uint16_t>(ticks.right));
  return f;
}

std::optional<AdcValues> decode_adc(const CanFrame& f) {
  if (f.id < can_id::kAdc00_03 || f.id > can_id::kAdc08_11 + 1 || f.dlc < 8) return std::nullopt;
  AdcValues v;
  v.first_channel = static_cast<int>(f.id - can_id::kAdc00_03) * 4;
  for (int i = 0; i < 4; ++i) v.raw[i] = get16(f, 2 * i);
  return v;
}

CanFrame encode_adc(const AdcValues& values) {
  CanFrame f = frame(can_id::kAdc00_03 + static_cast<uint32_t>(values.first_channel / 4));
  for (int i = 0; i < 4; ++i) put16(f, 2 * i, values.raw[i]);
  return f;
}

std::optional<GyroReading> decode_gyro(const CanFrame& f) {
  if (!is(f, can_id::kGyro, 8)) return std::nullopt;
  const auto angle = static_cast<int32_t>(get32(f, 0));
  const auto sigma = static_cast<int32_t>(get32(f, 4));
  GyroReading g;
  g.yaw = static_cast<double>(angle) / kGyroCountsPerDegree * M_PI / 180.0;
  const double sigma_deg = static_cast<double>(sigma) / 10000;
  const double root = std::sqrt(sigma_deg) * M_PI / 180.0;
  g.variance = root * root;
  return g;
}

CanFrame encode_gyro(int32_t angle_counts, int32_t sigma_counts) {
  CanFrame f = frame(can_id::kGyro);
  put32(f, 0, static_cast<uint32_t>(angle_counts));
  put32(f, 4, static_cast<uint32_t>(sigma_counts));
  return f;
}

std::optional<Tilt> decode_tilt(const CanFrame& f) {
  if (!is(f, can_id::kTiltCompass, 4)) return std::nullopt;
  const double a0 = (static_cast<double>(get16(f, 0)) - 32768.0) / 3932.0;
  const double a1 = (static_cast<double>(get16(f, 2)) - 32768.0) / 3932.0;
  return Tilt{std::asin(a0) * 180.0 / M_PI, std::asin(a1) * 180.0 / M_PI};
}

CanFrame encode_tilt(uint16_t left_right, uint16_t front_back) {
  CanFrame f = frame(can_id::kTiltCompass);
  put16(f, 0, left_right);
  put16(f, 2, front_back);
  return f;
}

std::optional<int> decode_rotunit_angle(const CanFrame& f) {
  if (!is(f, can_id::kRotunitAngle, 3)) return std::nullopt;
  return (f.data[1] << 8) | f.data[2];
}

CanFrame encode_rotunit_angle(int ticks) {
  CanFrame f = frame(can_id::kRotunitAngle);
  f.data[1] = static_cast<uint8_t>((ticks >> 8) & 0xFF);
  f.data[2] = static_cast<uint8_t>(ticks & 0xFF);
  return f;
}

}  // namespace macsim::kurt
