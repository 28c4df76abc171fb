// A step request's conditions and samples (SIM_STEP through the simulation dispatch, on a real
// world and the simulated KURT's readings, no DDS): bad fields are refused naming them with the
// world untouched; a request ends at the first check a group of its conditions holds, records its
// samples at every check, and traces every step's state hash when asked.
#include "simulation/step_conditions.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "macsim/client/supervisor_client.h"
#include "macsim/sim_core/world_loader.h"
#include "robots/simulated_robot.h"
#include "simulation/simulation_dispatch.h"
#include "support/child_process.h"

namespace macsim {
namespace {

namespace mm = macsim_msgs::msg::dds_;
namespace until = client::step_until;

RunSettings lockstep() {
  RunSettings settings;
  settings.paused = true;
  settings.real_time_factor = 0.0;
  return settings;
}

/// A lock-step runner on the small room with the robot's newest readings kept as the robot node
/// keeps them (merged after every step).
struct Stepper {
  Runner runner{load_world_file(test::source("worlds/small_room.xml")), lockstep()};
  SimulatedRobot kurt{runner, "kurt"};
  robot::Readings latest;

  /// Serves one SIM_STEP request to its reply (or the refusal).
  mm::SimulationReply_ serve(mm::SimulationRequest_ q, bool with_readings = true) {
    std::atomic<bool> stop{false};
    std::optional<mm::SimulationReply_> stepped;
    auto now = dispatch_simulation(
        q, runner,
        [&](const mm::SimulationReply_& r) {
          stepped = r;
          stop = true;
        },
        with_readings ? LatestReadings([this](const std::string&) { return &latest; })
                      : LatestReadings{});
    if (now) return *now;
    StepHooks hooks;
    hooks.after_step = [&](World&) {
      robot::Readings r = kurt.read();
      latest.stamp = r.stamp;
      if (r.odometry) latest.odometry = r.odometry;
      if (r.ground_truth) latest.ground_truth = r.ground_truth;
      if (r.crane) latest.crane = r.crane;
    };
    runner.run(stop, runner.world().steps() + 100000, hooks);
    EXPECT_TRUE(stepped.has_value());
    return stepped.value_or(mm::SimulationReply_{});
  }
};

mm::SimulationRequest_ steps(uint64_t n, uint32_t check_every, until::Condition condition,
                             uint32_t options = 0) {
  auto q = until::request(n, check_every, options);
  q.until({condition});
  return q;
}

TEST(StepConditions, BadFieldsAreRefusedNamingThemAndTheWorldIsUntouched) {
  Stepper s;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    mm::SimulationRequest_ request;
    bool readings;
    const char* names;
  };
  auto bad_reading = until::above(mm::STEP_READ_SIM_TIME, 1);
  bad_reading.reading(99);
  auto bad_test = until::above(mm::STEP_READ_SIM_TIME, 1);
  bad_test.test(9);
  auto huge_samples = until::request(1ull << 40, 1);
  huge_samples.samples({until::reading(mm::STEP_READ_SIM_TIME)});
  auto bad_options = until::request(10, 1, 64);
  auto negative_group = until::above(mm::STEP_READ_SIM_TIME, 1, -1);
  const Case cases[] = {
      {steps(10, 1, bad_reading), true, "until[0].reading"},
      {steps(10, 1, bad_test), true, "until[0].test"},
      {steps(10, 1, until::above(mm::STEP_READ_SIM_TIME, nan)), true, "until[0]: value"},
      {steps(10, 1, until::above(mm::STEP_READ_SIM_TIME, 1e308 * 10)), true, "until[0]: value"},
      {steps(10, 1, until::near(mm::STEP_READ_SIM_TIME, 1, -1)), true, "tolerance"},
      {steps(10, 1, until::stalled(mm::STEP_READ_TRUTH_X, 0, 0.01)), true, "until[0].value"},
      {steps(10, 1, negative_group), true, "until[0].group"},
      {steps(10, 1, until::above(mm::STEP_READ_OBJECT_Z, 1, 0, 424242)), true, "until[0].object_id"},
      {steps(10, 1, until::above(mm::STEP_READ_ODOMETRY_X, 1)), false, "until[0].robot"},
      {huge_samples, true, "samples:"},
      {bad_options, true, "step_options"},
  };
  const uint64_t hash = s.runner.world().state_hash();
  for (const auto& c : cases) {
    const auto reply = s.serve(c.request, c.readings);
    EXPECT_EQ(reply.code(), mm::ERR_INVALID_ARGUMENT) << c.names;
    EXPECT_NE(reply.message().find(c.names), std::string::npos) << reply.message();
  }
  EXPECT_EQ(s.runner.world().steps(), 0u);
  EXPECT_EQ(s.runner.world().state_hash(), hash);
}

TEST(StepConditions, ARequestEndsAtTheFirstCheckItsConditionHoldsWithTheSamplesOfEveryCheck) {
  Stepper s;
  const double dt = s.runner.world().step_size();
  auto q = steps(1000, 10, until::above(mm::STEP_READ_SIM_TIME, 25 * dt));
  q.samples({until::reading(mm::STEP_READ_SIM_TIME)});
  const auto reply = s.serve(q);
  ASSERT_EQ(reply.code(), mm::ERR_OK) << reply.message();
  EXPECT_EQ(reply.steps(), 30u);  // checked after 10, 20, 30 steps
  EXPECT_EQ(reply.ended_by(), 0);
  ASSERT_EQ(reply.samples().size(), 3u);
  EXPECT_DOUBLE_EQ(reply.samples()[0], 10 * dt);
  EXPECT_DOUBLE_EQ(reply.samples()[2], 30 * dt);
}

TEST(StepConditions, EveryConditionOfAGroupMustHoldAndAnyGroupEndsIt) {
  Stepper s;
  const double dt = s.runner.world().step_size();
  auto q = until::request(1000, 10);
  q.until({until::above(mm::STEP_READ_SIM_TIME, 5 * dt, 0),
           until::below(mm::STEP_READ_SIM_TIME, 5 * dt, 0),  // group 0 never holds
           until::above(mm::STEP_READ_SIM_TIME, 40 * dt, 1)});
  const auto reply = s.serve(q);
  EXPECT_EQ(reply.steps(), 50u);
  EXPECT_EQ(reply.ended_by(), 1);
  // Steps running out: no group ended it.
  const auto plain = s.serve(steps(20, 10, until::above(mm::STEP_READ_SIM_TIME, 1e3)));
  EXPECT_EQ(plain.steps(), 70u);
  EXPECT_EQ(plain.ended_by(), -1);
}

TEST(StepConditions, ADriveEndsWhenTheOdometryItPublishedPassesTheDistance) {
  Stepper s;
  s.kurt.execute(robot::Twist{0.3, 0.0});
  auto q = steps(5000, 10, until::above(mm::STEP_READ_ODOMETRY_X, 0.1), mm::STEP_HOLD_COMMANDS);
  q.samples({until::reading(mm::STEP_READ_ODOMETRY_X)});
  const auto reply = s.serve(q);
  ASSERT_EQ(reply.code(), mm::ERR_OK) << reply.message();
  EXPECT_EQ(reply.ended_by(), 0);
  ASSERT_GE(reply.samples().size(), 2u);
  const auto& x = reply.samples();
  EXPECT_GT(x.back(), 0.1);
  EXPECT_LE(x[x.size() - 2], 0.1);  // not a check later than needed
  EXPECT_EQ(x.back(), s.latest.odometry->x);
  EXPECT_LT(reply.steps(), 5000u);
}

TEST(StepConditions, AStallEndsARequestWhenTheReadingGainsNothingForItsTime) {
  Stepper s;  // the robot stands: its x gains nothing (no reading before the first check: the
              // stall counts from there)
  const auto reply = s.serve(steps(5000, 10, until::stalled(mm::STEP_READ_TRUTH_X, 0.5, 0.01)));
  EXPECT_EQ(reply.ended_by(), 0);
  const double t = reply.sim_time();
  EXPECT_GT(t, 0.5);
  EXPECT_LE(t, 0.5 + 20 * s.runner.world().step_size() + 1e-9);
  // Driving, it gains 1 cm every few checks and runs to the end.
  s.kurt.execute(robot::Twist{0.3, 0.0});
  const auto driving = s.serve(
      steps(500, 10, until::stalled(mm::STEP_READ_TRUTH_X, 0.5, 0.01), mm::STEP_HOLD_COMMANDS));
  EXPECT_EQ(driving.ended_by(), -1);
}

TEST(StepConditions, ReadingsFromBeforeAResetAreNotTakenForNewOnes) {
  // Driven 0.3 m, then reset: the newest readings kept are from before the reset (stamped
  // later than the new time). A stall counted from them would see no headway over 0.3 m.
  Stepper s;
  s.kurt.execute(robot::Twist{0.3, 0.0});
  s.serve(steps(5000, 10, until::above(mm::STEP_READ_TRUTH_X, 0.3), mm::STEP_HOLD_COMMANDS));
  ASSERT_GT(s.latest.ground_truth->position[0], 0.3);
  s.runner.world().reset(ResetScope::Everything);
  s.kurt.execute(robot::Twist{0.3, 0.0});
  const auto driving = s.serve(steps(300, 10, until::stalled(mm::STEP_READ_TRUTH_X, 0.2, 0.01),
                                     mm::STEP_HOLD_COMMANDS));
  EXPECT_EQ(driving.ended_by(), -1) << "stalled at " << driving.sim_time();
  EXPECT_EQ(driving.steps(), 300u);
}

TEST(StepConditions, TheStepTraceCoversEveryStepAndRepeats) {
  auto trace = [](uint64_t n) {
    Stepper s;
    return s.serve(until::request(n, 1, mm::STEP_TRACE_HASH)).step_trace();
  };
  EXPECT_EQ(trace(40), trace(40));
  EXPECT_NE(trace(40), trace(41));
  EXPECT_NE(trace(40), 0u);
}

TEST(StepConditions, HoldingTheCommandsOfARobotTheWorldLacksIsRefusedNamingIt) {
  Stepper s;
  auto q = until::request(100, 1, mm::STEP_HOLD_COMMANDS);
  q.hold_robots({"kurt", "rover"});
  const auto refused = s.serve(q);
  EXPECT_EQ(refused.code(), mm::ERR_INVALID_ARGUMENT);
  EXPECT_NE(refused.message().find("hold_robots names 'rover'"), std::string::npos)
      << refused.message();
  EXPECT_EQ(s.runner.world().steps(), 0u);
  q.hold_robots({"kurt"});
  EXPECT_EQ(s.serve(q).code(), mm::ERR_OK);
  EXPECT_EQ(s.runner.world().steps(), 100u);
}

TEST(StepConditions, ARequestCountsItsStepsForOtherThreadsAndACancelSaysSo) {
  Stepper s;
  const auto ended = s.serve(steps(300, 10, until::above(mm::STEP_READ_SIM_TIME, 0.1)));
  EXPECT_EQ(ended.ended_by(), 0);
  EXPECT_EQ(ended.steps_asked(), 300u);
  EXPECT_EQ(ended.steps_done(), ended.steps());  // ended early, at its first check past 0.1 s

  // Counted where another thread can read it; a pause cancels the request after 25 steps.
  auto counted = std::make_shared<std::atomic<uint64_t>>(0);
  std::optional<mm::SimulationReply_> cancelled;
  ASSERT_FALSE(dispatch_simulation(
      until::request(1000, 1), s.runner,
      [&](const mm::SimulationReply_& r) { cancelled = r; }, {}, counted));
  StepHooks hooks;
  for (int i = 0; i < 25; ++i) s.runner.step(hooks);
  EXPECT_EQ(counted->load(), 25u);
  s.runner.pause();
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(cancelled->code(), mm::ERR_NOT_APPLICABLE);
  EXPECT_EQ(cancelled->ended_by(), mm::STEP_CANCELLED);
  EXPECT_EQ(cancelled->steps_done(), 25u);
  EXPECT_EQ(cancelled->steps_asked(), 1000u);
  EXPECT_FALSE(s.runner.stepping_on_request());
}

}  // namespace
}  // namespace macsim
