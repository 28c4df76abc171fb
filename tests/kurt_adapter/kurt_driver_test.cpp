// The adapter's driver state machine: odometry from encoder frames to the last bit against an
// independently computed reference, ranges with invalid readings, the gyro's settling, and the
// command timeout.
#include "macsim/kurt/kurt_driver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace macsim::kurt {
namespace {

TEST(KurtDriver, OdometryFromEncoderFramesMatchesTheReferenceBitForBit) {
  // The frames and the expected values come from odometry_reference.py (the documented
  // formulas in Python, not this code): x, y, yaw, linear, angular after frames 5, 8, 18, 21.
  std::vector<std::pair<int, int>> frames;
  for (int i = 0; i < 5; ++i) frames.emplace_back(100, 100);
  for (int i = 0; i < 3; ++i) frames.emplace_back(150, -150);
  for (int i = 0; i < 4; ++i) frames.emplace_back(-200, -180);
  for (int i = 0; i < 6; ++i) frames.emplace_back(300, 250);
  frames.insert(frames.end(), {{0, 0}, {-32768, 32767}, {1, 0}});
  const std::map<int, std::array<double, 5>> expected{
      {5, {0x1.1ae5031a31dedp-7, 0.0, 0.0, 0x1.619e43e0be569p-3, 0.0}},
      {8, {0x1.1ae5031a31dedp-7, 0.0, -0x1.39b5bac12996ap-5, 0.0, -0x1.46c7f7de8b523p+0}},
      {18,
       {0x1.88f15ca63d37bp-6, -0x1.7f68fd74e6598p-11, -0x1.8664ff2944d24p-5, 0x1.e6399d5505b6fp-2,
        -0x1.b3b54a7e0f184p-3}},
      {21,
       {0x1.8912b40ae0313p-6, -0x1.812d085821bcdp-11, 0x1.5ed3a73a760abp+1, 0x1.c4a19e904fcafp-11,
        -0x1.16da6d1d7a4cfp-8}},
  };
  KurtDriver driver;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto [left, right] = frames[i];
    ASSERT_EQ(
        driver.handle(encode_encoder({static_cast<int16_t>(left), static_cast<int16_t>(right)})),
        Update::Odometry);
    auto want = expected.find(static_cast<int>(i + 1));
    if (want == expected.end()) continue;
    const PlanarOdometry o = driver.odometry();
    const auto& e = want->second;
    EXPECT_EQ(o.x, e[0]) << "frame " << i + 1;  // exact: the last bit
    EXPECT_EQ(o.y, e[1]) << "frame " << i + 1;
    EXPECT_EQ(o.yaw, e[2]) << "frame " << i + 1;
    EXPECT_EQ(o.linear, e[3]) << "frame " << i + 1;
    EXPECT_EQ(o.angular, e[4]) << "frame " << i + 1;
  }
  EXPECT_EQ(driver.encoder_frames(), frames.size());
}

TEST(KurtDriver, WheelJointsAccumulateTicksPerSide) {
  KurtDriver driver;
  for (int i = 0; i < 5; ++i) driver.handle(encode_encoder({2195, -2195}));  // half a turn each
  EXPECT_NEAR(std::fabs(driver.wheel_angle(0)), M_PI, 1e-9);
  EXPECT_NEAR(std::fabs(driver.wheel_angle(1)), M_PI, 1e-9);
  driver.handle(encode_encoder({5487, 0}));  // +90 degrees more on the left
  EXPECT_NEAR(std::remainder(driver.wheel_angle(0) - M_PI, 2 * M_PI), M_PI / 2, 1e-3);
}

TEST(KurtDriver, RangesComeWithTheThirdAdcFrameAndInvalidReadingsAreMarked) {
  KurtDriver driver;
  AdcValues a{0, {500, 50, 801, 0}};  // ir_back valid, ir_right_back too low, ir_right too high
  AdcValues b{4,
              {static_cast<uint16_t>(ir_raw_from_range(0.3)), 1001, 99,
               500}};              // sonar 1001 invalid, ir_left_front 99
  AdcValues c{8, {0, 500, 0, 0}};  // ir_left_back (channel 9)
  EXPECT_EQ(driver.handle(encode_adc(a)), Update::None);
  EXPECT_EQ(driver.handle(encode_adc(b)), Update::None);
  ASSERT_EQ(driver.handle(encode_adc(c)), Update::Ranges);
  const auto& r = driver.ranges();        // kRangeChannels' order
  EXPECT_DOUBLE_EQ(r[0], 0.08);           // raw 500: (30000/490)^(1/1.4) - 10 = 8.9 -> 8 cm
  EXPECT_DOUBLE_EQ(r[1], kInvalidRange);  // raw 50 < 100
  EXPECT_DOUBLE_EQ(r[2], kInvalidRange);  // raw 801 > 800
  EXPECT_NEAR(r[3], 0.3, 0.011);          // ir_right_front at 0.3 m, whole cm
  EXPECT_DOUBLE_EQ(r[4], kInvalidRange);  // ultrasound raw 1001 > 1000
  EXPECT_DOUBLE_EQ(r[5], kInvalidRange);  // ir_left_front raw 99
  EXPECT_DOUBLE_EQ(r[6], 0.08);           // ir_left raw 500
  EXPECT_DOUBLE_EQ(r[7], 0.08);           // ir_left_back raw 500
}

TEST(KurtDriver, GyroIsIgnoredForItsFirstHundredFrames) {
  KurtDriver driver;
  const CanFrame ten_degrees = encode_gyro(10 * 4992511, 10000);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(driver.handle(ten_degrees), Update::None);
  EXPECT_FALSE(driver.gyro());
  ASSERT_EQ(driver.handle(ten_degrees), Update::Imu);
  EXPECT_DOUBLE_EQ(driver.gyro()->yaw, 10 * M_PI / 180);
}

TEST(KurtDriver, ACommandThatIsNotFiniteIsIgnored) {
  // Found by the CAN fuzzer: a NaN speed reached an int conversion (undefined behaviour).
  KurtDriver driver;
  driver.command_twist(0.3, 0.0, 0.0);
  driver.command_twist(std::nan(""), 0.0, 0.1);
  driver.command_wheel_speeds({INFINITY, 0.1}, 0.1);
  EXPECT_EQ(driver.commanded(0.2).left, 0.3);  // the last good command holds
  EXPECT_EQ(driver.commanded(0.7).left, 0.0);  // and times out from when it came
  const auto control = decode_control(driver.control_frame(0.2));
  ASSERT_TRUE(control.has_value());
  EXPECT_EQ(control->left_cm, 30);
  EXPECT_EQ(speed_cm(std::nan("")), 0);
  EXPECT_EQ(speed_cm(INFINITY), 32767);
  EXPECT_EQ(rotunit_speed_command(std::nan("")), 0);
}

TEST(KurtDriver, CommandsMapAsTheDriverAndTimeOutAfterSixTenths) {
  KurtDriver driver;
  driver.command_twist(0.2, 0.5, 100.0);  // full track: 0.2 -+ 0.28 * 0.5 = 0.06, 0.34
  EXPECT_EQ(driver.control_frame(100.0), encode_speed_cm({0.06, 0.34}));
  const auto c = decode_control(driver.control_frame(100.59));
  EXPECT_EQ(c->left_cm, 6);
  EXPECT_EQ(c->right_cm, 34);
  const auto stopped = decode_control(driver.control_frame(100.61));
  EXPECT_EQ(stopped->left_cm, 0);
  EXPECT_EQ(stopped->right_cm, 0);
  driver.command_wheel_speeds({-0.25, 0.25}, 101.0);
  EXPECT_EQ(decode_control(driver.control_frame(101.0))->left_cm, -25);
}

TEST(KurtDriver, ATiltOutsideOneGIsIgnoredNotANaN) {
  KurtDriver driver;
  ASSERT_EQ(driver.handle(encode_tilt(0x87AE, 0x8000)), Update::Tilt);  // 30 degrees roll
  EXPECT_EQ(driver.handle(encode_tilt(0xFFFF, 0x0000)), Update::None);  // (65535-32768)/3932 > 1
  ASSERT_TRUE(driver.tilt());
  EXPECT_NEAR(driver.tilt()->roll_deg, 30.0, 1e-9);  // the last good reading stays
}

TEST(KurtDriver, RotunitSpeedsBeyondTheInt16SaturateInsteadOfReversing) {
  KurtDriver driver;
  const auto fast = decode_rotunit_speed(driver.command_rotunit(1e6));
  EXPECT_EQ(fast, 32767);
  EXPECT_EQ(decode_rotunit_speed(driver.command_rotunit(-1e6)), -32768);
  EXPECT_GT(driver.rotunit_speed(), -403.0);  // what was sent, not the unbounded request
  EXPECT_LT(driver.rotunit_speed(), -401.0);
}

TEST(KurtDriver, RotunitCommandIsQuantizedAndItsAngleComesFromTheRotunitsFrames) {
  KurtDriver driver;
  EXPECT_EQ(driver.command_rotunit(M_PI / 6), encode_rotunit_speed(M_PI / 6));
  EXPECT_DOUBLE_EQ(driver.rotunit_speed(), 42 * 2 * M_PI * 20 / 10240);  // 42 units, not pi/6
  EXPECT_FALSE(driver.rotunit_angle());
  ASSERT_EQ(driver.handle(encode_rotunit_angle(5120)), Update::Rotunit);
  EXPECT_DOUBLE_EQ(*driver.rotunit_angle(), M_PI);
}

}  // namespace
}  // namespace macsim::kurt
