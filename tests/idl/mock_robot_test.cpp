// The mock robot: commands come back as readings.
#include "macsim/robot/mock_robot.h"

#include <gtest/gtest.h>

#include <cmath>

namespace macsim::robot {
namespace {

TEST(MockRobot, OdometryFollowsTheCommandsUntilTheirTimeout) {
  Capabilities c;
  c.rotunit = c.crane = true;
  MockRobot mock("m", c);
  EXPECT_FALSE(mock.read().odometry.has_value());  // nothing moved yet
  mock.execute(Twist{0.2, 0.0});
  for (int i = 1; i <= 100; ++i) mock.advance(0.01 * i);  // 1 s: the command holds 0.6 s
  const Readings r = mock.read();
  ASSERT_TRUE(r.odometry.has_value());
  EXPECT_NEAR(r.odometry->x, 0.2 * 0.6, 1e-9);
  EXPECT_EQ(r.odometry->linear, 0.0);              // timed out
  EXPECT_FALSE(mock.read().odometry.has_value());  // nothing new since
  mock.execute(WheelSpeedCommand{-0.14, 0.14});    // turning in place at 1 rad/s
  mock.advance(1.1);
  const Readings turned = mock.read();
  EXPECT_NEAR(turned.odometry->yaw, 0.1, 1e-9);
  mock.execute(CraneTarget{0.3, 0.2, 0.1});
  mock.execute(RotunitSpeed{1.0});
  mock.advance(1.6);
  const Readings r2 = mock.read();
  ASSERT_TRUE(r2.crane && r2.rotunit);
  EXPECT_EQ(r2.crane->slew, 0.3);
  EXPECT_NEAR(r2.rotunit->angle, 0.5, 1e-9);
}

}  // namespace
}  // namespace macsim::robot
