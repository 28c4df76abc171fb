// The KURT's CAN protocol (uos/kurt_driver, C167 firmware): frame ids, and pure functions that
// encode the host's commands and decode the microcontroller's frames. Big-endian fields.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "macsim/kurt/can_frame.h"
#include "macsim/robot/kurt_drive.h"

namespace macsim::kurt {

/// CAN ids of the frames the driver uses.
namespace can_id {
inline constexpr uint32_t kControl = 0x001;       ///< host -> MC: control mode + payload
inline constexpr uint32_t kAdc00_03 = 0x005;      ///< MC -> host: ADC channels 0..3
inline constexpr uint32_t kAdc04_07 = 0x006;      ///< channels 4..7
inline constexpr uint32_t kAdc08_11 = 0x007;      ///< channels 8..11
inline constexpr uint32_t kEncoder = 0x009;       ///< ticks per side since the last frame
inline constexpr uint32_t kBumper = 0x00A;        ///< bumpers, remote control; ends a cycle
inline constexpr uint32_t kTiltCompass = 0x00D;   ///< tilt left/right, front/back, compass
inline constexpr uint32_t kGyro = 0x00E;          ///< gyro angle and sigma
inline constexpr uint32_t kRotunitAngle = 0x010;  ///< rotunit -> host: its angle
inline constexpr uint32_t kRotunitSpeed = 0x080;  ///< host -> rotunit: its speed
}  // namespace can_id

/// Control modes: bytes 0..1 of a CONTROL frame.
enum class ControlMode : uint16_t {
  Raw = 0x0000,
  Speed = 0x0001,
  SpeedCm = 0x0002,
  ActuatorOn = 0xFF00,
  ActuatorOff = 0xFF01,
  CalibrateGyro = 0xFF02,
  ResetGyro = 0xFF03,
  ResetSsc = 0xFF04,
  UpdateAngle = 0xFF05,
  McReset = 0xFFFF,
};

/// SPEED_CM's omega word: (|round(100 omega / pi)| << 2) | (sign << 1) | antiwindup.
uint16_t omega_word(double omega, bool antiwindup);
/// CONTROL SPEED_CM: each side in whole cm/s (truncated, int16), then the omega word. The
/// driver always sends omega 0 with anti-windup on (0x0001).
CanFrame encode_speed_cm(WheelSpeeds speeds, double omega = 0.0, bool antiwindup = true);
/// CONTROL RAW hard stop: PWM 1023 (the inverted PWM's stop) with the brake bit, both sides.
CanFrame encode_hard_stop();
/// CONTROL ACTUATOR_ON / ACTUATOR_OFF (the firmware's actuator output pin).
CanFrame encode_actuator(bool on);
/// SETROTUNIT: speed (rad/s) as the driver's command value, int16.
CanFrame encode_rotunit_speed(double speed);

/// A CONTROL frame as the microcontroller reads it (the emulator's side).
struct ControlCommand {
  ControlMode mode = ControlMode::Raw;
  int left_cm = 0, right_cm = 0;  ///< SPEED_CM: cm/s
  uint16_t omega = 0;             ///< SPEED_CM: the omega word
  bool hard_stop = false;         ///< RAW: both sides braked at PWM 1023
};
/// Decodes a CONTROL frame; nothing if the id or the mode is not one of the protocol's.
std::optional<ControlCommand> decode_control(const CanFrame& frame);
/// The rotunit's command value from a SETROTUNIT frame.
std::optional<int> decode_rotunit_speed(const CanFrame& frame);

/// ENCODER: ticks of the left and right side since the previous frame.
struct EncoderTicks {
  int16_t left = 0, right = 0;
};
std::optional<EncoderTicks> decode_encoder(const CanFrame& frame);
CanFrame encode_encoder(EncoderTicks ticks);

/// ADC00_03 / 04_07 / 08_11 / 12_15: the first channel's number and four raw values.
struct AdcValues {
  int first_channel = 0;
  std::array<uint16_t, 4> raw{};
};
std::optional<AdcValues> decode_adc(const CanFrame& frame);
/// The ADC frame holding channels first_channel..first_channel+3 (first_channel % 4 == 0).
CanFrame encode_adc(const AdcValues& values);

/// GYRO_MC1: angle (rad, as the driver scales it: raw / 4992511 deg) and its variance
/// ((sqrt(sigma_deg) * pi / 180)^2, sigma_deg = raw2 / 10000).
struct GyroReading {
  double yaw = 0.0;
  double variance = 0.0;
};
std::optional<GyroReading> decode_gyro(const CanFrame& frame);
/// GYRO_MC1 from raw counts: the angle's int32 and the sigma's int32 (sigma_deg * 10000).
CanFrame encode_gyro(int32_t angle_counts, int32_t sigma_counts);
/// Gyro counts per degree.
inline constexpr double kGyroCountsPerDegree = 4992511.0;

/// TILT_COMP: roll and pitch in degrees (asin((raw - 32768) / 3932), as the driver computes).
struct Tilt {
  double roll_deg = 0.0, pitch_deg = 0.0;
};
std::optional<Tilt> decode_tilt(const CanFrame& frame);
CanFrame encode_tilt(uint16_t left_right, uint16_t front_back);

/// GETROTUNIT: the rotunit's angle in ticks (kurt3d::kRotunitTicks per turn; byte 0 unused).
std::optional<int> decode_rotunit_angle(const CanFrame& frame);
CanFrame encode_rotunit_angle(int ticks);

/// The ADC channel of each range sensor, in the order of KurtRobot's range sensors' frames.
struct RangeChannel {
  const char* frame;  ///< sensor frame id, as the simulator and the real driver name it
  int channel;
  bool sonar;
};
inline constexpr std::array<RangeChannel, 8> kRangeChannels{{
    {"ir_back", 0, false},
    {"ir_right_back", 1, false},
    {"ir_right", 2, false},
    {"ir_right_front", 4, false},
    {"ultrasound_front", 5, true},
    {"ir_left_front", 6, false},
    {"ir_left", 7, false},
    {"ir_left_back", 9, false},
}};

}  // namespace macsim::kurt
