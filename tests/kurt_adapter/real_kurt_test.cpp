// The real robot's side of the typed commands: RealKurt carries out each command it has on the
// userspace CAN bus (the transport kurt_emulator speaks) and refuses the one it lacks, sending
// nothing. End to end with kurt_emulator: integration/kurt_adapter_test.cpp.
#include "macsim/kurt/real_kurt.h"

#include <gtest/gtest.h>

#include "macsim/kurt/kurt_can.h"
#include "macsim/kurt/kurt_driver.h"
#include "support/test_domain.h"

namespace macsim::kurt {
namespace {

using namespace std::chrono_literals;

TEST(RealKurt, CarriesOutEachCommandItHasOnTheBusAndRefusesTheCrane) {
  const int port = 6100 + 2 * test::unique_test_domain();
  auto adapter_side = open_can("udp:" + std::to_string(port) + ":" + std::to_string(port + 1));
  auto robot_side = open_can("udp:" + std::to_string(port + 1) + ":" + std::to_string(port));
  KurtDriver driver;
  double now = 10.0;
  RealKurt kurt(
      "kurt", driver, *adapter_side, [&now] { return now; }, [&now] { return now; });

  // Drive commands go to the driver: the next SPEED_CM frame carries them.
  EXPECT_TRUE(kurt.execute(robot::Twist{0.3, 0.0}));
  auto control = decode_control(driver.control_frame(now));
  ASSERT_TRUE(control);
  EXPECT_EQ(control->left_cm, 30);
  EXPECT_EQ(control->right_cm, 30);
  EXPECT_TRUE(kurt.execute(robot::WheelSpeedCommand{-0.2, 0.2}));
  control = decode_control(driver.control_frame(now));
  ASSERT_TRUE(control);
  EXPECT_EQ(control->left_cm, -20);
  EXPECT_EQ(control->right_cm, 20);

  // The rotunit's speed and the magnet go on the bus at once.
  EXPECT_TRUE(kurt.execute(robot::RotunitSpeed{1.0}));
  auto frame = robot_side->receive(1000ms);
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->id, can_id::kRotunitSpeed);
  EXPECT_TRUE(decode_rotunit_speed(*frame).has_value());
  EXPECT_TRUE(kurt.execute(robot::MagnetSwitch{true}));
  frame = robot_side->receive(1000ms);
  ASSERT_TRUE(frame);
  EXPECT_EQ(*frame, encode_actuator(true));

  // No crane on this robot's bus: refused, nothing sent.
  const robot::RobotCommand crane = robot::CraneTarget{0.3, 0.2, 0.1};
  EXPECT_FALSE(kurt.execute(crane));
  EXPECT_EQ(crane.name(), "crane");
  EXPECT_FALSE(robot_side->receive(100ms));
}

}  // namespace
}  // namespace macsim::kurt
