// The simulated KURT behind the robot interface: what it has by robot type, readings as the
// steps produce them, and commands on the robot of the world current when they run.
#include "robots/simulated_robot.h"

#include <gtest/gtest.h>

#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world_loader.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

WorldSpec one_robot(const std::string& type) {
  return load_world_string("<WORLD><ROBOT><ID>kurt</ID><TYPE>" + type + "</TYPE></ROBOT></WORLD>",
                           type + ".xml");
}

TEST(SimulatedRobot, HasWhatItsTypeHas) {
  Runner kurt3d(one_robot("kurt3d"));
  const auto c = SimulatedRobot(kurt3d, "kurt").capabilities();
  EXPECT_TRUE(c.ground_truth && c.ranges && c.imu && c.rotunit && c.laser && c.laser_rotating &&
              c.points && c.crane && c.magnet);
  Runner kurt2(one_robot("kurt2"));
  const auto c2 = SimulatedRobot(kurt2, "kurt").capabilities();
  EXPECT_TRUE(c2.laser);
  EXPECT_FALSE(c2.laser_rotating || c2.rotunit || c2.points || c2.crane || c2.magnet);
  EXPECT_THROW(SimulatedRobot(kurt3d, "nobody"), std::invalid_argument);
}

TEST(SimulatedRobot, ReadingsComeAsTheStepsProduceThem) {
  Runner runner(one_robot("kurt3d"));
  SimulatedRobot kurt(runner, "kurt");
  EXPECT_FALSE(kurt.read().odometry.has_value());
  kurt.execute(robot::Twist{0.3, 0.0});
  kurt.execute(robot::CraneTarget{0.2, 0.0, 0.0});
  int odometry = 0, scans = 0;
  for (int i = 0; i < 100; ++i) {  // 0.1 s: ten encoder frames, seven or eight sweeps
    runner.step();
    const robot::Readings r = kurt.read();
    EXPECT_EQ(r.stamp, runner.world().time());
    if (r.odometry) {
      ++odometry;
      EXPECT_TRUE(r.ground_truth && r.imu && r.crane);
      EXPECT_EQ(r.ranges.size(), 8u);
    }
    if (r.scan) {
      ++scans;
      EXPECT_EQ(r.scan->frame, "laser360");
      EXPECT_EQ(r.scan->ranges.size(), 181u);
      EXPECT_TRUE(r.rotunit.has_value());
    }
  }
  EXPECT_EQ(odometry, 10);
  EXPECT_GE(scans, 7);
  EXPECT_GT(runner.world().robot("kurt")->odometry().x, 0.0);
}

TEST(SimulatedRobot, AfterARestoreOrAResetItsFirstReadTakesEverything) {
  Runner runner(one_robot("kurt3d"));
  SimulatedRobot kurt(runner, "kurt");
  for (int i = 0; i < 30; ++i) runner.step();
  const WorldSnapshot at30 = runner.world().snapshot();
  for (int i = 0; i < 25; ++i) runner.step();
  kurt.read();
  runner.step();  // step 56: no encoder frame, no sweep
  EXPECT_FALSE(kurt.read().odometry.has_value());
  ASSERT_TRUE(runner.world().restore(at30).ok());  // to step 30: no frame produced there either
  EXPECT_TRUE(kurt.read().odometry.has_value());
  EXPECT_FALSE(kurt.read().odometry.has_value());
  // A robot first read after the world was put back (a resumed run whose session ends right
  // after a reset): everything, as its first read after one would have.
  runner.world().reset(ResetScope::Everything);
  SimulatedRobot late(runner, "kurt");
  EXPECT_TRUE(late.read().odometry.has_value());
}

TEST(SimulatedRobot, ActsOnTheRobotOfTheCurrentWorldAfterALoad) {
  Runner runner(one_robot("kurt3d"));
  SimulatedRobot kurt(runner, "kurt");
  for (int i = 0; i < 50; ++i) runner.step();
  kurt.read();
  bool loaded = false;
  EXPECT_EQ(
      runner.load([] { return one_robot("kurt3d"); }, [&](const LoadOutcome& o) { loaded = o.ok; }),
      LoadQueued::Yes);
  EXPECT_TRUE(runner.push([&kurt](World&) { kurt.execute(robot::MagnetSwitch{true}); }));
  for (int i = 0; i < 200 && !loaded; ++i) {
    runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::milliseconds(50));
    runner.apply_commands();
  }
  ASSERT_TRUE(loaded);
  EXPECT_TRUE(runner.world().robot_as<KurtRobot>("kurt")->state().magnet_on);
  runner.step();
  const robot::Readings r = kurt.read();  // the new world's first frame counts as new
  EXPECT_TRUE(r.odometry.has_value());
  EXPECT_EQ(r.stamp, runner.world().time());
}

}  // namespace
}  // namespace macsim::test
