// Robot commands as values: each is written as its name and numbers and read back as the same
// command; a name no type has, or numbers that do not fit, are refused saying which; a command
// is its type (as<T>() finds it, another type does not).
#include "macsim/robot/robot_command.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace macsim::robot {
namespace {

TEST(RobotCommand, EachIsWrittenAsItsNameAndNumbersAndReadBack) {
  for (const RobotCommand& command :
       std::vector<RobotCommand>{Twist{0.3, -0.2}, WheelSpeedCommand{0.1, 0.2}, RotunitSpeed{3.0},
                                 CraneTarget{0.1, 0.2, 0.3}, MagnetSwitch{true}}) {
    const auto back = decode_command(command.name(), command.values());
    ASSERT_TRUE(back) << command.name();
    EXPECT_EQ(back->name(), command.name());
    EXPECT_EQ(back->values(), command.values());
  }
  std::string why;
  EXPECT_FALSE(decode_command("twist", {0.1}, &why));
  EXPECT_EQ(why, "robot command 'twist' does not take 1 numbers");
  EXPECT_FALSE(decode_command("fly", {1.0}, &why));
  EXPECT_EQ(why, "no robot command 'fly'");
}

TEST(RobotCommand, ACommandIsItsTypeAndNoOther) {
  const RobotCommand command = Twist{0.3, -0.1};
  ASSERT_NE(command.as<Twist>(), nullptr);
  EXPECT_EQ(command.as<Twist>()->angular, -0.1);
  EXPECT_EQ(command.as<WheelSpeedCommand>(), nullptr);
  EXPECT_EQ(command.name(), "twist");
  EXPECT_FALSE(register_command_type<Twist>());  // a name is taken once
  const auto names = command_type_names();
  for (const char* name : {"crane", "magnet", "rotunit", "twist", "wheel_speeds"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
}

}  // namespace
}  // namespace macsim::robot
