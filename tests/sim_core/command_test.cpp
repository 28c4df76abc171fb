// Robot commands are types from end to end: each built-in command, pushed to the runner for the
// KURT3D, the KURT2 and the diff-drive base, acts on the robot that has it (the world differs
// from its twin that got no command) and is refused by the one that lacks it, changing nothing
// and saying which robot and which command.
#include "macsim/sim_core/command.h"

#include <gtest/gtest.h>

#include <set>

#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/runner.h"
#include "support/world_helpers.h"

namespace macsim {
namespace {

WorldSpec three_types() {
  WorldSpec spec;
  spec.name = "three_types";
  for (const auto& [name, type, y] :
       {std::tuple<const char*, const char*, double>{"k3", "kurt3d", 0.0},
        {"k2", "kurt2", 2.0},
        {"rover", "diff_drive", -2.0}}) {
    RobotSpec robot;
    robot.name = name;
    robot.type = type;
    robot.pose = test::at(0, y, 0);
    spec.robots.push_back(robot);
  }
  return spec;
}

TEST(RobotCommands, EachActsOnTheRobotThatHasItAndIsRefusedByTheOneThatLacksIt) {
  const std::vector<robot::RobotCommand> commands{
      robot::Twist{0.3, 0.2}, robot::WheelSpeedCommand{0.2, 0.25}, robot::RotunitSpeed{2.0},
      robot::CraneTarget{0.4, 0.3, 0.05}, robot::MagnetSwitch{true}};
  const std::map<std::string, std::set<std::string>> has{
      {"k3", {"twist", "wheel_speeds", "rotunit", "crane", "magnet"}},
      {"k2", {"twist", "wheel_speeds"}},
      {"rover", {"twist", "wheel_speeds"}}};
  for (const auto& [name, kinds] : has) {
    for (const auto& command : commands) {
      const std::string what = name + " " + std::string(command.name());
      std::vector<std::string> said;
      const ScopedLogSink capture(
          [&said](LogLevel, const std::string& line) { said.push_back(line); });
      Runner with(three_types(), RunSettings{true, 0.0});
      Runner twin(three_types(), RunSettings{true, 0.0});
      ASSERT_TRUE(with.push(robot_command(name, command))) << what;
      for (int i = 0; i < 300; ++i) {
        with.step();
        twin.step();
      }
      const bool acted = with.world().state_hash() != twin.world().state_hash();
      if (kinds.count(std::string(command.name()))) {
        EXPECT_TRUE(acted) << what;
        EXPECT_TRUE(said.empty()) << what << ": " << said.front();
      } else {
        EXPECT_FALSE(acted) << what;
        ASSERT_EQ(said.size(), 1u) << what;
        EXPECT_NE(said[0].find("robot '" + name + "' has no command '" +
                               std::string(command.name()) + "'"),
                  std::string::npos)
            << said[0];
      }
    }
  }
}

TEST(RobotCommands, ACommandForNoRobotIsRefusedNamingIt) {
  std::vector<std::string> said;
  const ScopedLogSink capture([&said](LogLevel, const std::string& line) { said.push_back(line); });
  Runner runner(three_types(), RunSettings{true, 0.0});
  ASSERT_TRUE(runner.push(robot_command("nobody", robot::Twist{0.1, 0.0})));
  runner.step();
  ASSERT_EQ(said.size(), 1u);
  EXPECT_NE(said[0].find("no robot 'nobody'"), std::string::npos) << said[0];
}

}  // namespace
}  // namespace macsim
