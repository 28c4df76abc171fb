// Robot messages as runner commands: hostile numbers never become commands; a command whose
// robot is not in the world when it runs does nothing.
#include "robot_commands.h"

#include <gtest/gtest.h>

#include "support/world_helpers.h"

namespace macsim::test {
namespace {

TEST(RobotCommands, NonFiniteNumbersAreDropped) {
  const double nan = std::nan(""), inf = INFINITY;
  EXPECT_FALSE(robot_commands::twist("kurt", nan, 0).has_value());
  EXPECT_FALSE(robot_commands::twist("kurt", 0, inf).has_value());
  EXPECT_FALSE(robot_commands::wheel_speeds("kurt", {0, -inf}).has_value());
  EXPECT_FALSE(robot_commands::rotunit("kurt", nan).has_value());
  EXPECT_FALSE(robot_commands::crane("kurt", {0, nan, 0}).has_value());
  EXPECT_TRUE(robot_commands::twist("kurt", 1e308, 0).has_value());  // finite: the driver clamps
}

TEST(RobotCommands, EachCommandReachesItsRobot) {
  World world(shipped_world("small_room.xml"));
  (*robot_commands::twist("kurt", 0.2, 0.0))(world);
  EXPECT_GT(world.robot("kurt")->state().commanded.left, 0.0);
  (*robot_commands::wheel_speeds("kurt", {0.1, -0.1}))(world);
  EXPECT_LT(world.robot("kurt")->state().commanded.right, 0.0);
  (*robot_commands::rotunit("kurt", 0.5))(world);
  EXPECT_GT(world.robot("kurt")->rotunit_speed(), 0.0);
  (*robot_commands::crane("kurt", {0.3, 0.1, 0.05}))(world);
  EXPECT_EQ(world.robot("kurt")->state().crane.slew, 0.3);
  robot_commands::magnet("kurt", true)(world);
  EXPECT_TRUE(world.robot("kurt")->state().magnet_on);
}

TEST(RobotCommands, AMissingRobotIsSkipped) {
  World world(shipped_world("small_room.xml"));
  const uint64_t hash = world.state_hash();
  (*robot_commands::twist("nobody", 0.2, 0.0))(world);
  robot_commands::magnet("nobody", true)(world);
  EXPECT_EQ(world.state_hash(), hash);
}

}  // namespace
}  // namespace macsim::test
