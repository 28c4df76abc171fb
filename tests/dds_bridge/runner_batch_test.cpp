// The bridge's three kinds of command in one batch: a world load (as SIM_LOAD_WORLD queues it),
// then a supervisor request and a cmd_vel (as their readers queue them). The later two must act
// on the new world; the old one is freed at the swap, so any use of it is a use-after-free that
// this test, built with AddressSanitizer (ctest label `asan`), reports.
#include <gtest/gtest.h>

#include <thread>

#include "macsim/client/supervisor_requests.h"
#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world_loader.h"
#include "robots/simulated_robot.h"
#include "supervisor/supervisor_dispatch.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

namespace mm = macsim_msgs::msg::dds_;
namespace rq = client::supervisor;

/// Applies commands until `done` holds (the load is parsed on its own thread).
void apply_until(Runner& runner, const std::function<bool()>& done) {
  for (int i = 0; i < 200 && !done(); ++i) {
    runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::milliseconds(50));
    runner.apply_commands();
  }
  ASSERT_TRUE(done());
}

TEST(RunnerBatch, ALoadThenASupervisorRequestAndACmdVelActOnTheNewWorld) {
  Runner runner(shipped_world("DemoWorld_v1.xml"));
  run_for(runner.world(), 0.05);
  ASSERT_TRUE(runner.snapshots().save("before", runner.world().snapshot()).ok());
  const ObjectId box = id_of(runner.world(), "environment_01/box_red_small");
  auto supervise = [&runner](mm::SupervisorRequest_ request, mm::SupervisorReply_* reply) {
    EXPECT_TRUE(runner.push([&runner, request, reply](World& world) {
      *reply = dispatch(request, world, runner.snapshots());
    }));
  };

  std::optional<LoadOutcome> loaded;
  EXPECT_EQ(runner.load([] { return shipped_world("DemoWorld_v1.xml"); },
                        [&](const LoadOutcome& outcome) { loaded = outcome; }),
            LoadQueued::Yes);
  mm::SupervisorReply_ destroyed, restored, hashed;
  supervise(rq::destroy_object(box), &destroyed);
  // As RobotNode posts a cmd_vel: a command calling the simulated KURT's interface.
  SimulatedRobot kurt(runner, "kurt");
  EXPECT_TRUE(runner.push([&kurt](World&) { kurt.execute(robot::Twist{0.3, 0.0}); }));
  supervise(rq::restore_snapshot("before"), &restored);
  supervise(rq::state_hash(), &hashed);
  apply_until(runner, [&] { return hashed.sequence_number() == 0 && hashed.hash() != 0; });

  ASSERT_TRUE(loaded && loaded->ok) << (loaded ? loaded->error : "no outcome");
  EXPECT_EQ(runner.generation(), 1u);
  EXPECT_EQ(runner.world().steps(), 0u);  // the new world
  EXPECT_EQ(destroyed.code(), mm::ERR_OK) << destroyed.message();
  EXPECT_EQ(runner.world().objects().object(box), nullptr);  // destroyed in the new world
  EXPECT_GT(runner.world().robot_as<KurtRobot>("kurt")->state().commanded.left, 0.0);
  // The old world's named snapshot went with it.
  EXPECT_EQ(restored.code(), mm::ERR_INVALID_ARGUMENT);
  EXPECT_NE(restored.message().find("no snapshot named 'before'"), std::string::npos);
  EXPECT_EQ(hashed.hash(), runner.world().state_hash());
  runner.step();  // and the new world steps with the command
  EXPECT_GT(runner.world().robot_as<KurtRobot>("kurt")->state().active.left, 0.0);
}

TEST(RunnerBatch, ARefusedLoadLeavesLaterCommandsOnTheOldWorld) {
  Runner runner(shipped_world("DemoWorld_v1.xml"));
  const ObjectId box = id_of(runner.world(), "environment_01/box_red_small");
  std::optional<LoadOutcome> loaded;
  EXPECT_EQ(runner.load([] { return load_world_file(source("worlds/no_such.xml")); },
                        [&](const LoadOutcome& outcome) { loaded = outcome; }),
            LoadQueued::Yes);
  mm::SupervisorReply_ destroyed;
  destroyed.code(-1);
  EXPECT_TRUE(runner.push([&](World& world) {
    destroyed = dispatch(rq::destroy_object(box), world, runner.snapshots());
  }));
  apply_until(runner, [&] { return destroyed.code() != -1; });
  ASSERT_TRUE(loaded.has_value());
  EXPECT_FALSE(loaded->ok);
  EXPECT_NE(loaded->error.find("no_such.xml"), std::string::npos) << loaded->error;
  EXPECT_EQ(runner.generation(), 0u);
  EXPECT_EQ(destroyed.code(), mm::ERR_OK);
  EXPECT_EQ(runner.world().objects().object(box), nullptr);
}

}  // namespace
}  // namespace macsim::test
