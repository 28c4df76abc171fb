// The KURT CAN codec against byte vectors worked out by hand from the documented layouts
// (kurt.md section 1): ids, big-endian fields, two's complement, the omega word.
#include "macsim/kurt/kurt_can.h"

#include <gtest/gtest.h>

#include <cmath>

namespace macsim::kurt {
namespace {

CanFrame bytes(uint32_t id, std::array<uint8_t, 8> data) {
  CanFrame f;
  f.id = id;
  f.data = data;
  return f;
}

TEST(KurtCan, SpeedCmTruncatesToWholeCentimetresWithNegativeSpeedsInTwosComplement) {
  // 0.30 m/s -> 30 = 0x001E; -0.305 m/s -> -30.5 -> -30 = 0xFFE2; omega word 0x0001.
  EXPECT_EQ(encode_speed_cm({0.30, -0.305}),
            bytes(0x001, {0x00, 0x02, 0x00, 0x1E, 0xFF, 0xE2, 0x00, 0x01}));
  // -3.0 m/s -> -300 = 0xFED4; 0.009 m/s -> 0.
  EXPECT_EQ(encode_speed_cm({-3.0, 0.009}),
            bytes(0x001, {0x00, 0x02, 0xFE, 0xD4, 0x00, 0x00, 0x00, 0x01}));
}

TEST(KurtCan, OmegaWordPacksMagnitudeSignAndAntiWindup) {
  // o = round(100 * 0.5 / pi) = 16: 16 << 2 = 0x40, sign bit 1 (value 2), anti-windup bit 0.
  EXPECT_EQ(omega_word(0.5, true), 0x0041);
  EXPECT_EQ(omega_word(-0.5, true), 0x0043);
  EXPECT_EQ(omega_word(-0.5, false), 0x0042);
  EXPECT_EQ(omega_word(0.0, true), 0x0001);
  EXPECT_EQ(omega_word(0.0, false), 0x0000);
  const CanFrame f = encode_speed_cm({0.1, 0.1}, -0.5, true);
  EXPECT_EQ(f.data[6], 0x00);
  EXPECT_EQ(f.data[7], 0x43);
}

TEST(KurtCan, HardStopBrakesBothSidesAtTheInvertedPwmsStop) {
  // RAW mode, byte 2 = dir 0 << 1 | brake 1, PWM 1023 = 0x03FF, the same on the right.
  EXPECT_EQ(encode_hard_stop(), bytes(0x001, {0x00, 0x00, 0x01, 0x03, 0xFF, 0x01, 0x03, 0xFF}));
  const auto decoded = decode_control(encode_hard_stop());
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->mode, ControlMode::Raw);
  EXPECT_TRUE(decoded->hard_stop);
  // RAW with a running PWM is not a hard stop.
  EXPECT_FALSE(decode_control(bytes(0x001, {0, 0, 0x01, 0x01, 0x00, 0x01, 0x03, 0xFF}))->hard_stop);
}

TEST(KurtCan, ActuatorAndRotunitCommands) {
  EXPECT_EQ(encode_actuator(true), bytes(0x001, {0xFF, 0x00, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(encode_actuator(false), bytes(0x001, {0xFF, 0x01, 0, 0, 0, 0, 0, 0}));
  // pi/6 rad/s / 2 pi * 10240 / 20 = 42.67 -> 42 = 0x002A; the negative -42 = 0xFFD6.
  EXPECT_EQ(encode_rotunit_speed(M_PI / 6), bytes(0x080, {0x00, 0x2A, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(encode_rotunit_speed(-M_PI / 6), bytes(0x080, {0xFF, 0xD6, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(decode_rotunit_speed(encode_rotunit_speed(-M_PI / 6)), -42);
}

TEST(KurtCan, ControlFramesDecodeAsTheMicrocontrollerReadsThem) {
  const auto c = decode_control(bytes(0x001, {0x00, 0x02, 0xFF, 0x38, 0x00, 0xC8, 0x00, 0x43}));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->mode, ControlMode::SpeedCm);
  EXPECT_EQ(c->left_cm, -200);
  EXPECT_EQ(c->right_cm, 200);
  EXPECT_EQ(c->omega, 0x0043);
  EXPECT_EQ(decode_control(bytes(0x001, {0xFF, 0x00, 0, 0, 0, 0, 0, 0}))->mode,
            ControlMode::ActuatorOn);
  EXPECT_FALSE(decode_control(bytes(0x001, {0x12, 0x34, 0, 0, 0, 0, 0, 0})));  // no such mode
  EXPECT_FALSE(decode_control(bytes(0x009, {0x00, 0x02, 0, 0, 0, 0, 0, 0})));  // not CONTROL
}

TEST(KurtCan, EncoderTicksAreSignedBigEndian) {
  const auto t = decode_encoder(bytes(0x009, {0xFF, 0x38, 0x00, 0xC8, 0, 0, 0, 0}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->left, -200);
  EXPECT_EQ(t->right, 200);
  const auto extremes = decode_encoder(bytes(0x009, {0x80, 0x00, 0x7F, 0xFF, 0, 0, 0, 0}));
  EXPECT_EQ(extremes->left, -32768);
  EXPECT_EQ(extremes->right, 32767);
  EXPECT_EQ(encode_encoder({-200, 200}), bytes(0x009, {0xFF, 0x38, 0x00, 0xC8, 0, 0, 0, 0}));
  EXPECT_FALSE(decode_encoder(bytes(0x00A, {})));
}

TEST(KurtCan, AdcFramesCarryFourChannelsFromTheirId) {
  const auto a = decode_adc(bytes(0x006, {0x01, 0xF4, 0x00, 0x64, 0x03, 0x20, 0x00, 0x0A}));
  ASSERT_TRUE(a);
  EXPECT_EQ(a->first_channel, 4);
  EXPECT_EQ(a->raw, (std::array<uint16_t, 4>{500, 100, 800, 10}));
  EXPECT_EQ(decode_adc(bytes(0x005, {}))->first_channel, 0);
  EXPECT_EQ(decode_adc(bytes(0x007, {}))->first_channel, 8);
  EXPECT_EQ(decode_adc(bytes(0x008, {}))->first_channel, 12);
  EXPECT_FALSE(decode_adc(bytes(0x009, {})));
  EXPECT_EQ(encode_adc(*a), bytes(0x006, {0x01, 0xF4, 0x00, 0x64, 0x03, 0x20, 0x00, 0x0A}));
}

TEST(KurtCan, GyroAngleAndSigmaAsTheDriverScalesThem) {
  // 4992511 counts = 0x004C2DFF = 1 degree; sigma 10000 = 1 degree -> variance (pi/180)^2.
  const auto g = decode_gyro(bytes(0x00E, {0x00, 0x4C, 0x2D, 0xFF, 0x00, 0x00, 0x27, 0x10}));
  ASSERT_TRUE(g);
  EXPECT_DOUBLE_EQ(g->yaw, M_PI / 180);
  EXPECT_DOUBLE_EQ(g->variance, (M_PI / 180) * (M_PI / 180));
  // -90 degrees: -449325990 = 0xE537D45A in two's complement.
  const auto minus90 = decode_gyro(bytes(0x00E, {0xE5, 0x37, 0xD4, 0x5A, 0, 0, 0, 0}));
  EXPECT_DOUBLE_EQ(minus90->yaw, -M_PI / 2);
  EXPECT_EQ(encode_gyro(-449325990, 10000),
            bytes(0x00E, {0xE5, 0x37, 0xD4, 0x5A, 0x00, 0x00, 0x27, 0x10}));
}

TEST(KurtCan, TiltIsTheArcsineOfTheCentredAcceleration) {
  // 32768 is level; 32768 + 1966 = 0x87AE is half a g: asin(0.5) = 30 degrees.
  const auto t = decode_tilt(bytes(0x00D, {0x87, 0xAE, 0x80, 0x00, 0, 0, 0, 0}));
  ASSERT_TRUE(t);
  EXPECT_NEAR(t->roll_deg, 30.0, 1e-9);
  EXPECT_DOUBLE_EQ(t->pitch_deg, 0.0);
  EXPECT_EQ(encode_tilt(0x87AE, 0x8000), bytes(0x00D, {0x87, 0xAE, 0x80, 0x00, 0, 0, 0, 0}));
}

TEST(KurtCan, RotunitAngleSkipsByteZero) {
  // Bytes 1..2 = 0x0A00 = 2560 ticks of 10240: a quarter turn.
  const auto ticks = decode_rotunit_angle(bytes(0x010, {0x77, 0x0A, 0x00, 0, 0, 0, 0, 0}));
  ASSERT_TRUE(ticks);
  EXPECT_EQ(*ticks, 2560);
  EXPECT_DOUBLE_EQ(rotunit_angle_from_ticks(*ticks), M_PI / 2);
  EXPECT_EQ(decode_rotunit_angle(encode_rotunit_angle(2560)), 2560);
}

}  // namespace
}  // namespace macsim::kurt
