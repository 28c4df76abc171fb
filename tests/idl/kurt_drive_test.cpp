// The real driver's kinematics: cmd_vel mapping, SPEED_CM truncation, encoder ticks, odometry.
#include "macsim/robot/kurt_drive.h"

#include <gtest/gtest.h>

#include <cmath>

namespace macsim {
namespace {

const KurtDriveParams kParams;
// One tick in metres: wheel perimeter 0.379 m over 21950 ticks.
const double kMetresPerTick = 0.379 / 21950.0;

TEST(KurtDrive, WheelRadiusFromPerimeter) {
  EXPECT_NEAR(kParams.wheel_radius(), 0.060320, 1e-6);
}

TEST(KurtDrive, TwistUsesTheFullAxisLengthLikeTheRealDriver) {
  auto straight = wheel_speeds_from_twist(0.3, 0.0, kParams);
  EXPECT_DOUBLE_EQ(straight.left, 0.3);
  EXPECT_DOUBLE_EQ(straight.right, 0.3);
  auto spin = wheel_speeds_from_twist(0.0, 1.0, kParams);
  EXPECT_DOUBLE_EQ(spin.left, -0.28);  // not -0.14: the driver multiplies by the full track
  EXPECT_DOUBLE_EQ(spin.right, 0.28);
  auto arc = wheel_speeds_from_twist(0.2, -0.5, kParams);
  EXPECT_DOUBLE_EQ(arc.left, 0.2 + 0.14);
  EXPECT_DOUBLE_EQ(arc.right, 0.2 - 0.14);
}

TEST(KurtDrive, SpeedCmTruncatesTowardsZero) {
  auto q = quantize_to_speed_cm({0.299, -0.299});
  EXPECT_DOUBLE_EQ(q.left, 0.29);
  EXPECT_DOUBLE_EQ(q.right, -0.29);
  auto small = quantize_to_speed_cm({0.009, -0.0099});
  EXPECT_EQ(small.left, 0.0);
  EXPECT_EQ(small.right, 0.0);
}

TEST(EncoderCounter, CountsTicksPerTurnAndSign) {
  EncoderCounter counter(21950);
  EXPECT_EQ(counter.ticks_since_last(2 * M_PI * 0.01), 219);  // floor(219.5)
  EXPECT_EQ(counter.ticks_since_last(2 * M_PI * 0.02), 220);  // 439 - 219
  EXPECT_EQ(counter.ticks_since_last(2 * M_PI * 0.02), 0);
  EXPECT_EQ(counter.ticks_since_last(0.0), -439);
}

TEST(EncoderCounter, SaturatesAtTheFramesInt16Range) {
  EncoderCounter counter(21950);
  EXPECT_EQ(counter.ticks_since_last(2 * M_PI * 10), 32767);
  counter.reset(0.0);
  EXPECT_EQ(counter.ticks_since_last(-2 * M_PI * 10), -32768);
}

TEST(KurtOdometry, StraightFramesAddUpToTheTravelledDistance) {
  KurtOdometry odom(kParams);
  for (int i = 0; i < 100; ++i) odom.integrate_frame(579, 579);
  const auto e = odom.estimate();
  EXPECT_NEAR(e.x, 100 * 579 * kMetresPerTick, 1e-12);
  EXPECT_EQ(e.y, 0.0);
  EXPECT_EQ(e.yaw, 0.0);
  EXPECT_NEAR(e.linear, 579 * kMetresPerTick / 0.01, 1e-12);  // fixed 10 ms frame
  EXPECT_EQ(e.angular, 0.0);
}

TEST(KurtOdometry, TurningInPlaceCounterClockwiseIsPositiveYaw) {
  KurtOdometry odom(kParams);
  odom.integrate_frame(-100, 100);
  const auto e = odom.estimate();
  // yaw = (right - left) / axis_length * turning_adaptation
  EXPECT_NEAR(e.yaw, 200 * kMetresPerTick / 0.28 * 0.69, 1e-15);
  EXPECT_EQ(e.x, 0.0);
  EXPECT_EQ(e.y, 0.0);
  EXPECT_NEAR(e.angular, 200 * kMetresPerTick / 0.01 / 0.28 * 0.69, 1e-12);
}

TEST(KurtOdometry, ArcToTheRightMovesForwardAndRight) {
  KurtOdometry odom(kParams);
  odom.integrate_frame(200, 100);
  const auto e = odom.estimate();
  const double distance = 150 * kMetresPerTick;
  const double turn = 100 * kMetresPerTick / 0.28 * 0.69;  // clockwise
  EXPECT_NEAR(e.yaw, -turn, 1e-15);
  // The driver moves the whole step along the new heading.
  EXPECT_NEAR(e.x, distance * std::cos(turn), 1e-15);
  EXPECT_NEAR(e.y, -distance * std::sin(turn), 1e-15);
}

TEST(KurtOdometry, YawWrapsIntoMinusPiToPi) {
  KurtOdometry odom(kParams);
  // Each frame turns by 2000 ticks' worth; go well past half a turn.
  const double per_frame = 4000 * kMetresPerTick / 0.28 * 0.69;
  const int frames = static_cast<int>(std::ceil(1.5 * M_PI / per_frame));
  for (int i = 0; i < frames; ++i) odom.integrate_frame(-2000, 2000);
  const auto e = odom.estimate();
  EXPECT_LE(e.yaw, M_PI);
  EXPECT_GT(e.yaw, -M_PI);
  EXPECT_NEAR(std::remainder(e.yaw - frames * per_frame, 2 * M_PI), 0.0, 1e-9);
  EXPECT_LT(e.yaw, 0.0);  // 1.5 pi counter-clockwise reads as -0.5 pi
}

}  // namespace
TEST(KurtDrive, SpeedCmTruncatesTowardsZeroAndSaturatesAtTheFramesInt16) {
  EXPECT_EQ(speed_cm(0.305), 30);
  EXPECT_EQ(speed_cm(-0.305), -30);
  EXPECT_EQ(speed_cm(0.009), 0);
  EXPECT_EQ(speed_cm(1000.0), 32767);  // not wrapped to a reverse speed
  EXPECT_EQ(speed_cm(-1000.0), -32768);
}

}  // namespace macsim
