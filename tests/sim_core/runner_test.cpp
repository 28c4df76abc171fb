// The runner: queued commands run at the step with the world current then, runs are
// deterministic, a world is parsed off the simulation thread and swapped in between batches,
// and what belongs to one world (named snapshots, generation) goes with it.
#include "macsim/sim_core/runner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <future>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world_bounds.h"
#include "macsim/sim_core/world_loader.h"
#include "sim_core/named_request.h"
#include "support/child_process.h"
#include "support/world_helpers.h"

namespace macsim {
namespace {

using test::small_room;

using test::Named;

/// Another request type, which no executor takes unless a test sets one.
struct Other final : Request {
  std::string_view name() const override { return "set_density"; }
  std::vector<uint8_t> wire() const override { return {}; }
};

TEST(Runner, ARequestOfATypeNoExecutorTakesCannotBeQueued) {
  Runner runner(small_room(), RunSettings{true, 0.0});
  std::vector<std::string> ran;
  runner.set_executor<Named>([&](const Named& q, const Command&, World&) {
    ran.push_back(q.operation);
    return false;
  });
  // Refused by its type, whatever its name or source says.
  EXPECT_FALSE(runner.push(request_command<Other>(CommandSource::Supervisor)));
  EXPECT_TRUE(runner.push(request_command<Named>(CommandSource::Supervisor, "set_density")));
  runner.apply_commands();
  EXPECT_EQ(ran, std::vector<std::string>{"set_density"});
  EXPECT_EQ(runner.commands_run(CommandSource::Supervisor), 1u);
  // Taken once an executor takes its type; refused again once that executor is gone.
  int others = 0;
  runner.set_executor<Other>([&](const Other&, const Command&, World&) { return ++others > 0; });
  EXPECT_TRUE(runner.push(request_command<Other>(CommandSource::Supervisor)));
  runner.apply_commands();
  EXPECT_EQ(others, 1);
  runner.set_executor<Other>({});
  EXPECT_FALSE(runner.push(request_command<Other>(CommandSource::Supervisor)));
  // A queued request whose executor went meanwhile runs nowhere.
  EXPECT_TRUE(runner.push(request_command<Named>(CommandSource::Supervisor, "late")));
  runner.set_executor<Named>({});
  runner.apply_commands();
  EXPECT_EQ(ran.size(), 1u);
  EXPECT_TRUE(runner.takes(KeepRobotCommands{}));  // the runner's own needs none
}

TEST(Runner, CommandsRunOnlyWhenTheRunnerSteps) {
  Runner runner(small_room());
  int applied = 0;
  std::thread producer([&] {
    for (int i = 0; i < 100; ++i) EXPECT_TRUE(runner.push([&applied](World&) { ++applied; }));
  });
  producer.join();
  EXPECT_EQ(applied, 0);  // nothing touched the world from the producer's thread
  runner.step();
  EXPECT_EQ(applied, 100);
  runner.step();
  EXPECT_EQ(applied, 100);
}

TEST(Runner, CommandsRunInArrivalOrderBeforeTheStep) {
  Runner runner(small_room());
  std::vector<uint64_t> seen_at_step;
  EXPECT_TRUE(runner.push([&](World& w) { seen_at_step.push_back(w.steps()); }));
  EXPECT_TRUE(runner.push([&](World& w) { seen_at_step.push_back(w.steps() + 100); }));
  runner.step();
  ASSERT_EQ(seen_at_step.size(), 2u);
  EXPECT_EQ(seen_at_step[0], 0u);  // ran before the step advanced time
  EXPECT_EQ(seen_at_step[1], 100u);
  EXPECT_EQ(runner.world().steps(), 1u);
}

TEST(Runner, ARepeatAnsweredByItsExecutorIsNotCountedAsRun) {
  Runner runner(small_room());
  std::set<std::string> answered;
  runner.set_executor<Named>([&](const Named& q, const Command& c, World&) {
    if (!answered.insert(q.operation).second) runner.answered_repeat(c);  // sent again
    return false;
  });
  const Command first = request_command<Named>(CommandSource::Supervisor, "find_object");
  const Command other = request_command<Named>(CommandSource::Supervisor, "add_force");
  for (const Command& c : {first, first, other, first}) ASSERT_TRUE(runner.push(Command(c)));
  runner.step();
  EXPECT_EQ(runner.commands_run(CommandSource::Supervisor), 2u);  // two ran, two were repeats
  EXPECT_EQ(runner.commands_run(CommandSource::Simulation), 0u);
}

TEST(Runner, ARobotCommandGoesToTheRobotsExecutorWhenOneIsSetElseToTheWorldsRobot) {
  Runner runner(small_room());
  std::vector<std::string> served;  // what the robot interface was given
  runner.set_robot_executor([&](const Command& c, World& world) {
    served.push_back(c.target + " " + std::string(operation_name(c)));
    return run_robot_command(c, world);
  });
  ASSERT_TRUE(runner.push(robot_command("kurt", robot::Twist{0.3, 0.0})));
  for (int i = 0; i < 200; ++i) runner.step();
  EXPECT_EQ(served, std::vector<std::string>{"kurt twist"});
  EXPECT_EQ(runner.commands_run(CommandSource::Robot), 1u);
  const double moved = runner.world().robot("kurt")->base_footprint_pose().position.x();
  EXPECT_GT(moved, 0.01);  // it acted through the executor
  // Without one, the world's robot takes it itself.
  runner.set_robot_executor({});
  ASSERT_TRUE(runner.push(robot_command("kurt", robot::Twist{0.0, 0.0})));
  runner.step();
  EXPECT_EQ(served.size(), 1u);
  EXPECT_EQ(runner.commands_run(CommandSource::Robot), 2u);
}

TEST(Runner, SameWorldAndCommandsGiveBitIdenticalStates) {
  auto run = [] {
    Runner runner(small_room());
    for (int i = 0; i < 2000; ++i) {
      if (i % 100 == 0) {
        EXPECT_TRUE(runner.push([](World& w) {
          w.robot("kurt")->execute(robot::Twist{0.3, 0.4}, w.time());
        }));
      }
      runner.step();
    }
    return runner.world().snapshot().bytes;
  };
  EXPECT_EQ(run(), run());
}

TEST(Runner, CommandsAfterALoadInTheSameBatchActOnTheNewWorld) {
  Runner runner(small_room());
  const World* old_world = &runner.world();
  for (int i = 0; i < 10; ++i) runner.step();
  std::vector<const World*> seen;
  LoadOutcome outcome;
  EXPECT_TRUE(runner.push([&](World& w) { seen.push_back(&w); }));
  std::promise<void> parsed;
  EXPECT_EQ(runner.load(
                [&] {
                  WorldSpec spec = small_room();
                  parsed.set_value();
                  return spec;
                },
                [&](const LoadOutcome& o) { outcome = o; }),
            LoadQueued::Yes);
  EXPECT_TRUE(runner.push([&](World& w) {
    seen.push_back(&w);
    w.robot("kurt")->execute(robot::Twist{0.3, 0.0}, w.time());  // a cmd_vel right after the load
  }));
  parsed.get_future().wait();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the promise is set just after
  EXPECT_EQ(runner.apply_commands(), 3u);
  ASSERT_TRUE(outcome.ok) << outcome.error;
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0], old_world);
  EXPECT_EQ(seen[1], &runner.world());  // the world current when it ran: the new one
  EXPECT_EQ(runner.world().steps(), 0u);
  EXPECT_EQ(runner.generation(), 1u);
  EXPECT_EQ(runner.world().robot_as<KurtRobot>("kurt")->state().active.left,
            0.0);  // set at the step
  EXPECT_GT(runner.world().robot_as<KurtRobot>("kurt")->state().commanded.left, 0.0);
}

TEST(Runner, ALoadStillParsingHoldsLaterCommandsWhileTheWorldRunsOn) {
  Runner runner(small_room());
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  LoadOutcome outcome;
  bool done = false;
  EXPECT_EQ(runner.load(
                [released] {
                  released.wait();
                  return small_room();
                },
                [&](const LoadOutcome& o) {
                  outcome = o;
                  done = true;
                }),
            LoadQueued::Yes);
  int later = 0;
  EXPECT_TRUE(runner.push([&](World&) { ++later; }));
  for (int i = 0; i < 5; ++i) runner.step();  // the old world steps on; the command waits
  EXPECT_EQ(later, 0);
  EXPECT_FALSE(done);
  EXPECT_EQ(runner.world().steps(), 5u);
  release.set_value();
  ASSERT_TRUE(
      runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::seconds(10)));
  runner.apply_commands();
  EXPECT_TRUE(done);
  EXPECT_TRUE(outcome.ok);
  EXPECT_EQ(later, 1);
  EXPECT_EQ(runner.world().steps(), 0u);
}

TEST(Runner, ABadWorldIsRefusedAndTheOldOneRunsOn) {
  Runner runner(small_room());
  for (int i = 0; i < 3; ++i) runner.step();
  const uint64_t hash = runner.world().state_hash();
  std::vector<LoadOutcome> outcomes;
  // One load at a time: each is answered before the next is asked.
  auto load = [&](std::function<WorldSpec()> parse) {
    const std::size_t before = outcomes.size();
    ASSERT_EQ(runner.load(std::move(parse), [&](const LoadOutcome& o) { outcomes.push_back(o); }),
              LoadQueued::Yes);
    for (int i = 0; i < 100 && outcomes.size() == before; ++i) {
      runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::milliseconds(100));
      runner.apply_commands();
    }
    ASSERT_EQ(outcomes.size(), before + 1);
  };
  load([] { return load_world_file(test::source("worlds/no_such_world.xml")); });
  load([] { return load_world_string("<WORLD><BOX>", "broken.xml"); });
  load([] {  // its robot is not the same
    return load_world_string("<WORLD><ROBOT><ID>kurt2</ID><TYPE>kurt3d</TYPE></ROBOT></WORLD>",
                             "r.xml");
  });
  load([] {  // nor of the same type
    return load_world_string("<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt2</TYPE></ROBOT></WORLD>",
                             "t.xml");
  });
  load([]() -> WorldSpec { throw std::runtime_error("disk on fire"); });
  ASSERT_EQ(outcomes.size(), 5u);
  for (const auto& o : outcomes) EXPECT_FALSE(o.ok);
  EXPECT_NE(outcomes[0].error.find("no_such_world.xml"), std::string::npos) << outcomes[0].error;
  EXPECT_NE(outcomes[1].error.find("broken.xml:1"), std::string::npos) << outcomes[1].error;
  EXPECT_NE(outcomes[2].error.find("same robots"), std::string::npos) << outcomes[2].error;
  EXPECT_NE(outcomes[3].error.find("names and types"), std::string::npos) << outcomes[3].error;
  EXPECT_NE(outcomes[4].error.find("disk on fire"), std::string::npos) << outcomes[4].error;
  EXPECT_EQ(outcomes[0].code, ErrorCode::BadFile);
  EXPECT_EQ(outcomes[2].code, ErrorCode::InvalidArgument);
  EXPECT_EQ(runner.generation(), 0u);
  EXPECT_EQ(runner.world().state_hash(), hash);  // untouched
}

TEST(Runner, NamedSnapshotsBelongToOneWorld) {
  Runner runner(small_room());
  ASSERT_TRUE(runner.snapshots().save("start", runner.world().snapshot()).ok());
  const WorldSnapshot kept = runner.world().snapshot();
  bool loaded = false;
  EXPECT_EQ(runner.load([] { return small_room(); }, [&](const LoadOutcome& o) { loaded = o.ok; }),
            LoadQueued::Yes);
  for (int i = 0; i < 100 && !loaded; ++i) {
    runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::milliseconds(100));
    runner.apply_commands();
  }
  ASSERT_TRUE(loaded);
  EXPECT_TRUE(runner.snapshots().empty());
  // A snapshot is of a description: the same file loaded again takes it; another world refuses it.
  EXPECT_TRUE(runner.world().restore(kept).ok());
  World other(load_world_string(R"(<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT>
      <BOX><ID>b</ID><POS>1,0,0.05</POS><SIZE>0.1,0.1,0.1</SIZE></BOX></WORLD>)",
                                "other.xml"));
  const Status refused = other.restore(kept);
  EXPECT_EQ(refused.code, ErrorCode::InvalidArgument);
  EXPECT_NE(refused.message.find("fingerprint"), std::string::npos);
}

TEST(Runner, StepRequestsRunWhilePausedAndAnswerAfterTheLastStep) {
  Runner runner(small_room(), RunSettings{true, 0.0});
  std::atomic<bool> stop{false};
  int answered = 0;
  uint64_t answered_at = 0;
  std::vector<uint64_t> published;
  StepHooks hooks;
  hooks.after_step = [&](World& w) { published.push_back(w.steps()); };
  EXPECT_TRUE(runner.push([&](World&) {
    EXPECT_TRUE(runner.request_steps(3, [&](bool completed) {
      EXPECT_TRUE(completed);
      ++answered;
      answered_at = runner.world().steps();
      stop = true;
    }));
    EXPECT_FALSE(runner.request_steps(1, nullptr));  // one request at a time
  }));
  runner.run(stop, 100, hooks);
  EXPECT_EQ(answered, 1);
  EXPECT_EQ(answered_at, 3u);
  EXPECT_EQ(published, (std::vector<uint64_t>{1, 2, 3}));  // every step's data out first
}

TEST(Runner, AStepRequestEndsAtTheFirstCheckItsConditionHoldsAndFlushesBeforeItsAnswer) {
  Runner runner(small_room(), RunSettings{true, 0.0});
  std::atomic<bool> stop{false};
  std::vector<uint64_t> checked_at, each_at;
  std::vector<std::string> order;
  bool completed = false;
  StepRequest request;
  request.steps = 1000;
  request.check_every = 10;
  // True from step 35 on: first seen at the check after step 40.
  request.until = [&](const World& w) {
    checked_at.push_back(w.steps());
    return w.steps() >= 35;
  };
  request.each_step = [&](const World& w) { each_at.push_back(w.steps()); };
  request.publish_at_end = true;
  request.done = [&](bool c) {
    completed = c;
    order.push_back("done");
    stop = true;
  };
  StepHooks hooks;
  hooks.after_step = [&](World&) {
    ASSERT_NE(runner.step_request(), nullptr);
    EXPECT_TRUE(runner.step_request()->publish_at_end);  // the hooks see what the request wants
  };
  hooks.request_end = [&](World& w) { order.push_back("end at " + std::to_string(w.steps())); };
  EXPECT_TRUE(runner.push([&](World&) { EXPECT_TRUE(runner.request_steps(std::move(request))); }));
  runner.run(stop, 2000, hooks);
  EXPECT_TRUE(completed);
  EXPECT_EQ(runner.world().steps(), 40u);
  EXPECT_EQ(checked_at, (std::vector<uint64_t>{10, 20, 30, 40}));
  EXPECT_EQ(each_at.size(), 40u);
  EXPECT_EQ(order, (std::vector<std::string>{"end at 40", "done"}));
  EXPECT_EQ(runner.step_request(), nullptr);
}

TEST(Runner, AStepRequestThatHoldsCommandsKeepsTheRobotDrivingPastTheCommandTimeout) {
  // The robot is sent 0.3 m/s once; a request of 2 s (past the 0.6 s command timeout) that holds
  // commands keeps it driving, one that does not lets it stop.
  auto travelled = [](bool hold) {
    Runner runner(small_room(), RunSettings{true, 0.0});
    std::atomic<bool> stop{false};
    KurtRobot& robot = dynamic_cast<KurtRobot&>(*runner.world().robots().front());
    const double x0 = robot.base_footprint_pose().position.x();
    robot.command_twist(0.3, 0.0, runner.world().time());
    StepRequest request;
    request.steps = static_cast<uint64_t>(std::lround(2.0 / runner.world().step_size()));
    request.hold_commands = hold;
    request.done = [&](bool) { stop = true; };
    EXPECT_TRUE(runner.push([&](World&) { runner.request_steps(std::move(request)); }));
    runner.run(stop, 100000, {});
    return robot.base_footprint_pose().position.x() - x0;
  };
  const double held = travelled(true), timed_out = travelled(false);
  EXPECT_GT(held, 0.45);       // about 0.3 m/s for 2 s
  EXPECT_LT(timed_out, 0.25);  // stopped after 0.6 s
}

TEST(Runner, RobotCommandsAreDroppedUntilTheNextStepWhenAsked) {
  // A step request cut by a kill goes on with the set-points it had: the copies its client
  // sends again before the repeat are dropped, while paused and at the first step; the next
  // step's commands run again.
  Runner runner(small_room(), RunSettings{true, 0.0});
  const std::string name = runner.world().robots().front()->name();
  KurtRobot& robot = dynamic_cast<KurtRobot&>(*runner.world().robots().front());
  const auto x = [&] { return robot.base_footprint_pose().position.x(); };
  std::atomic<bool> stop{false};
  const auto steps = [&](uint64_t n) {
    StepRequest request;
    request.steps = n;
    request.done = [&](bool) { stop = true; };
    ASSERT_TRUE(runner.push(
        [&runner, request](World&) mutable { runner.request_steps(std::move(request)); }));
    stop = false;
    runner.run(stop, 100000, {});
  };
  const double x0 = x();
  runner.drop_robot_commands_until_next_step();
  ASSERT_TRUE(runner.push(robot_command(name, robot::Twist{0.4, 0.0})));  // dropped, paused
  steps(200);
  const double still = x();
  EXPECT_NEAR(still, x0, 1e-3);                                           // the twist never acted
  ASSERT_TRUE(runner.push(robot_command(name, robot::Twist{0.4, 0.0})));  // runs
  steps(200);
  EXPECT_GT(x() - still, 0.02);  // it drove once the first step had passed
}

TEST(Runner, AStepRequestHoldsTheCommandsOfTheRobotsItNamesOnly) {
  // Both robots are sent a drive once; a 2 s request holding "kurt" keeps the KURT3D driving
  // past the 0.6 s command timeout and lets the rover stop; naming both holds both.
  const auto travelled = [](const std::string& held) {
    Runner runner(load_world_file(test::source("worlds/two_robots.xml")), RunSettings{true, 0.0});
    std::atomic<bool> stop{false};
    const auto x = [&](const char* robot) {
      return runner.world().robot(robot)->base_footprint_pose().position.x();
    };
    const double kurt0 = x("kurt"), rover0 = x("rover");
    for (const char* robot : {"kurt", "rover"})
      runner.world().robot(robot)->execute(robot::Twist{0.3, 0.0}, runner.world().time());
    StepRequest request;
    request.steps = static_cast<uint64_t>(std::lround(2.0 / runner.world().step_size()));
    request.hold_commands = true;
    request.hold_robots = held;
    request.done = [&](bool) { stop = true; };
    EXPECT_TRUE(runner.push([&](World&) { runner.request_steps(std::move(request)); }));
    runner.run(stop, 100000, {});
    return std::make_pair(x("kurt") - kurt0, x("rover") - rover0);
  };
  const auto [kurt, rover] = travelled("kurt");
  EXPECT_GT(kurt, 0.45);   // about 0.3 m/s for 2 s
  EXPECT_LT(rover, 0.25);  // stopped after 0.6 s
  EXPECT_GT(rover, 0.05);  // but it drove until then
  const auto [kurt_both, rover_both] = travelled("kurt,rover");
  EXPECT_GT(kurt_both, 0.45);
  EXPECT_GT(rover_both, 0.45);
}

TEST(Runner, AResetThatTakesTheTimeBackCancelsAStepRequestWithNoStepAfterIt) {
  Runner runner(small_room(), RunSettings{true, 0.0});
  std::atomic<bool> stop{false};
  std::optional<bool> completed;
  StepRequest request;
  request.steps = 1000;
  request.until = [](const World&) { return false; };
  request.done = [&](bool c) {
    completed = c;
    stop = true;
  };
  EXPECT_TRUE(runner.push([&](World&) { runner.request_steps(std::move(request)); }));
  StepHooks hooks;
  hooks.after_step = [&](World& w) {
    if (w.steps() == 5) {
      EXPECT_TRUE(runner.push([](World& world) { world.reset(ResetScope::Everything); }));
    }
  };
  bool flushed_before_answer = false;  // what was held for the request's end goes out first
  hooks.request_end = [&](World&) { flushed_before_answer = !completed.has_value(); };
  runner.run(stop, 2000, hooks);
  ASSERT_TRUE(completed.has_value());
  EXPECT_FALSE(*completed);
  EXPECT_TRUE(flushed_before_answer);
  EXPECT_FALSE(runner.stepping_on_request());
  EXPECT_EQ(runner.world().steps(), 0u);  // reset, and not stepped on for the cancelled request
}

TEST(Runner, ARobotCommandSentBeforeAResetAndRunAfterItNeverActs) {
  // A controller (sender 7) drives, asks for a reset, and its drive command (its 5th sample)
  // arrives only after the reset: dropped. Its next command, and another sender's, act.
  Runner runner(small_room(), RunSettings{true, 0.0});
  runner.set_executor<Named>([](const Named&, const Command&, World& world) {
    world.reset(ResetScope::Everything);
    return true;
  });
  const auto& robot = *runner.world().robots().front();
  const std::string name = robot.name();
  const auto sent = [&](uint8_t sender, uint64_t sequence, double speed) {
    Command c = robot_command(name, robot::Twist{speed, 0.0});
    c.sent_by = Sender{{sender}, sequence};
    return c;
  };
  Command reset = request_command<Named>(CommandSource::Supervisor, "reset");
  reset.sent_before = {Sender{{7}, 5}, Sender{{9}, 2}};
  const auto travelled = [&](std::vector<Command> commands) {
    for (auto& c : commands) EXPECT_TRUE(runner.push(std::move(c)));
    runner.apply_commands();
    const double x0 = runner.world().robots().front()->base_footprint_pose().position.x();
    for (int i = 0; i < 200; ++i) runner.step();
    return runner.world().robots().front()->base_footprint_pose().position.x() - x0;
  };
  EXPECT_NEAR(travelled({reset, sent(7, 5, 0.3), sent(7, 4, 0.3)}), 0.0, 1e-3);  // settling
  EXPECT_EQ(runner.commands_sent_before_reset(), 2u);
  EXPECT_EQ(runner.commands_run(CommandSource::Robot), 0u);
  EXPECT_GT(travelled({sent(7, 6, 0.3)}), 0.03);  // sent after the reset
  EXPECT_GT(travelled({sent(8, 1, 0.3)}), 0.03);  // another sender
  EXPECT_GT(travelled({robot_command(name, robot::Twist{0.3, 0.0})}), 0.03);  // sender unknown
  EXPECT_EQ(runner.commands_sent_before_reset(), 2u);
  // A reset that did not act (refused) drops nothing.
  runner.set_executor<Named>([](const Named&, const Command&, World&) { return false; });
  reset.sent_before = {Sender{{8}, 10}};
  EXPECT_GT(travelled({reset, sent(8, 2, 0.3)}), 0.03);
  EXPECT_EQ(runner.commands_sent_before_reset(), 2u);
}

TEST(Runner, AStepRequestWaitsForTheCommandItNamesAndHoldsOnesWrittenAfterIt) {
  // A controller (sender 7) wrote its 3rd command (drive) and asked for 300 steps naming it; DDS
  // delivers that command 0.1 s late, together with its 4th (stop), written after the request.
  Runner runner(small_room(), RunSettings{true, 0.0});
  const std::string name = runner.world().robots().front()->name();
  const auto sent = [&](uint64_t sequence, double speed) {
    Command c = robot_command(name, robot::Twist{speed, 0.0});
    c.sent_by = Sender{{7}, sequence};
    return c;
  };
  std::atomic<bool> stop{false};
  std::optional<bool> completed;
  const auto asked = std::chrono::steady_clock::now();
  StepHooks hooks;
  bool delivered = false;
  hooks.before_step = [&] {
    if (delivered || std::chrono::steady_clock::now() - asked < std::chrono::milliseconds(100))
      return;
    delivered = true;
    EXPECT_TRUE(runner.push(sent(3, 0.3)));
    EXPECT_TRUE(runner.push(sent(4, 0.0)));
  };
  std::optional<double> first_step_after;  // s after the request
  uint64_t robot_commands_at_first_step = 0;
  hooks.after_step = [&](World&) {
    if (first_step_after) return;
    first_step_after =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
    robot_commands_at_first_step = runner.commands_run(CommandSource::Robot);
  };
  const double x0 = runner.world().robots().front()->base_footprint_pose().position.x();
  StepRequest request;
  request.steps = 300;
  request.commands_named = {Sender{{7}, 3}};
  request.done = [&](bool done) {
    completed = done;
    stop = true;
  };
  request.refused = [&](const std::string& why) { ADD_FAILURE() << why; };
  ASSERT_TRUE(runner.request_steps(std::move(request)));
  runner.run(stop, 1000, hooks);
  ASSERT_TRUE(completed.has_value());
  EXPECT_TRUE(*completed);
  ASSERT_TRUE(first_step_after.has_value());
  EXPECT_GE(*first_step_after, 0.1);                  // the first step waited for it
  EXPECT_EQ(robot_commands_at_first_step, 1u);        // and took it before its first tick
  EXPECT_EQ(runner.commands_held_for_request(), 1u);  // the stop waited for the request's end
  const double x1 = runner.world().robots().front()->base_footprint_pose().position.x();
  EXPECT_GT(x1 - x0, 0.03);  // it drove the whole request
  // After the request the stop acts.
  EXPECT_EQ(runner.apply_commands(), 1u);
  EXPECT_EQ(runner.commands_run(CommandSource::Robot), 2u);
}

TEST(Runner, AStepRequestWhoseNamedCommandNeverComesIsRefusedNamingItWithNoStep) {
  RunSettings settings{true, 0.0};
  settings.command_wait = 0.2;
  Runner runner(small_room(), settings);
  std::atomic<bool> stop{false};
  std::string why;
  StepRequest request;
  request.steps = 5;
  request.commands_named = {Sender{{0x09, 0xab}, 12}};
  request.done = [&](bool) { ADD_FAILURE() << "answered as stepped"; };
  request.refused = [&](const std::string& w) {
    why = w;
    stop = true;
  };
  ASSERT_TRUE(runner.request_steps(std::move(request)));
  const auto asked = std::chrono::steady_clock::now();
  runner.run(stop, 1000, StepHooks{});
  EXPECT_GE(std::chrono::steady_clock::now() - asked, std::chrono::milliseconds(200));
  EXPECT_NE(why.find("robot command 12 of writer 09.ab.00"), std::string::npos) << why;
  EXPECT_NE(why.find("none of that writer arrived"), std::string::npos) << why;
  EXPECT_EQ(runner.world().steps(), 0u);
  EXPECT_FALSE(runner.stepping_on_request());
  // The next request (naming nothing) steps as ever.
  EXPECT_TRUE(runner.request_steps(2, [&](bool done) { EXPECT_TRUE(done); }));
  runner.step(StepHooks{});
  runner.step(StepHooks{});
  EXPECT_EQ(runner.world().steps(), 2u);
}

TEST(Runner, APauseCancelsAHugeStepRequest) {
  Runner runner(small_room(), RunSettings{true, 0.0});
  std::atomic<bool> stop{false};
  std::optional<bool> completed;
  EXPECT_TRUE(runner.push([&](World&) {
    runner.request_steps(1'000'000'000'000'000'000ull, [&](bool c) {
      completed = c;
      stop = true;
    });
  }));
  StepHooks hooks;
  hooks.after_step = [&](World& w) {
    if (w.steps() == 5) {
      EXPECT_TRUE(runner.push([&](World&) { runner.pause(); }));  // as SIM_PAUSE does
    }
  };
  runner.run(stop, 1000, hooks);
  ASSERT_TRUE(completed.has_value());
  EXPECT_FALSE(*completed);
  EXPECT_FALSE(runner.stepping_on_request());
  EXPECT_LE(runner.world().steps(), 7u);
}

TEST(Runner, AWorldGoneNonFiniteAtRunTimePausesWithAnEventNamingTheObject) {
  Runner runner(small_room(), RunSettings{false, 0.0});
  std::atomic<bool> stop{false};
  std::vector<WorldEvent> events;
  StepHooks hooks;
  hooks.after_step = [&](World& w) {
    for (auto& e : w.take_events()) events.push_back(e);
    if (w.steps() == 10) {
      // The largest force a request may give, on a light ball: beyond 1000 m/s in one step.
      EXPECT_TRUE(runner.push([](World& world) {
        const ObjectId ball = *world.objects().find_object("green_ball");
        ASSERT_TRUE(world.edit().add_force(ball, {0, 0, bounds::kMaxForce}).ok());
      }));
    }
    if (w.steps() == 50) stop = true;  // reached only if the runner ran on
  };
  std::thread watchdog([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    stop = true;  // run() returns once paused and stopped
  });
  runner.run(stop, 1000, hooks);
  watchdog.join();
  EXPECT_TRUE(runner.settings().paused);
  EXPECT_EQ(runner.world().steps(), 11u);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, WorldEvent::Type::Instability);
  EXPECT_EQ(events[0].subject, "green_ball");
  EXPECT_TRUE(runner.world()
                  .objects()
                  .object_state(*runner.world().objects().find_object("green_ball"))
                  .value.pose.position.allFinite());
}

TEST(Runner, RealTimeFactorRefusesNonsense) {
  Runner runner(small_room());
  EXPECT_FALSE(runner.set_real_time_factor(std::nan("")));
  EXPECT_FALSE(runner.set_real_time_factor(-1));
  EXPECT_FALSE(runner.set_real_time_factor(INFINITY));
  EXPECT_FALSE(runner.set_real_time_factor(1e-6));  // waits too long to serve anyone
  EXPECT_FALSE(runner.set_real_time_factor(1e-300));
  EXPECT_EQ(runner.settings().real_time_factor, 1.0);
  EXPECT_TRUE(runner.set_real_time_factor(kMinRealTimeFactor));
  EXPECT_TRUE(runner.set_real_time_factor(0));
}

TEST(Runner, OneLoadAtATime) {
  Runner runner(small_room());
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  int done = 0;
  EXPECT_EQ(runner.load(
                [released] {
                  released.wait();
                  return small_room();
                },
                [&](const LoadOutcome&) { ++done; }),
            LoadQueued::Yes);
  EXPECT_EQ(runner.load([] { return small_room(); }, [&](const LoadOutcome&) { ++done; }),
            LoadQueued::LoadRunning);
  release.set_value();
  for (int i = 0; i < 100 && done == 0; ++i) {
    runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::milliseconds(100));
    runner.apply_commands();
  }
  EXPECT_EQ(done, 1);
  EXPECT_EQ(runner.load([] { return small_room(); }, nullptr),
            LoadQueued::Yes);  // the next one is welcome
}

TEST(Runner, TheCommandQueueIsCappedAndTakesCommandsAgainOnceServed) {
  RunSettings settings;
  settings.max_queued_commands = 3;
  Runner runner(small_room(), settings);
  int ran = 0;
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runner.push([&](World&) { ++ran; }));
  EXPECT_FALSE(runner.push([&](World&) { ran += 100; }));  // refused: never runs
  bool parsed = false;
  EXPECT_EQ(runner.load(
                [&] {
                  parsed = true;
                  return small_room();
                },
                nullptr),
            LoadQueued::QueueFull);  // a load counts as a command
  EXPECT_NE(runner.queue_full_message().find("--max-queued-commands"), std::string::npos);
  EXPECT_NE(runner.queue_full_message().find("3"), std::string::npos);
  EXPECT_EQ(runner.apply_commands(), 3u);
  EXPECT_EQ(ran, 3);
  EXPECT_FALSE(parsed);  // nothing of a refused load runs
  // Served: the queue takes as many again.
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runner.push([&](World&) { ++ran; }));
  EXPECT_FALSE(runner.push([&](World&) { ran += 100; }));
  runner.step();
  EXPECT_EQ(ran, 6);
  // A command running holds its place until its batch is done: a command it pushes counts too.
  bool inner = false, third = true;
  EXPECT_TRUE(runner.push([&](World&) {
    inner = runner.push([&](World&) { ++ran; });
    EXPECT_TRUE(runner.push([&](World&) { ++ran; }));
    third = runner.push([&](World&) { ran += 100; });
  }));
  EXPECT_EQ(runner.apply_commands(), 1u);  // what it pushed runs with the next batch
  EXPECT_TRUE(inner);
  EXPECT_FALSE(third);
  EXPECT_EQ(runner.apply_commands(), 2u);
  EXPECT_EQ(ran, 8);
}

TEST(Runner, CommandsHeldBehindALoadStillParsingFillTheQueue) {
  RunSettings settings;
  settings.max_queued_commands = 3;
  Runner runner(small_room(), settings);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::optional<LoadOutcome> outcome;
  EXPECT_EQ(runner.load(
                [released] {
                  released.wait();
                  return small_room();
                },
                [&](const LoadOutcome& o) { outcome = o; }),
            LoadQueued::Yes);
  int ran = 0;
  EXPECT_TRUE(runner.push([&](World&) { ++ran; }));
  EXPECT_TRUE(runner.push([&](World&) { ++ran; }));
  EXPECT_FALSE(runner.push([&](World&) { ran += 100; }));
  for (int i = 0; i < 3; ++i) runner.step();  // the old world steps on; nothing is served
  EXPECT_EQ(ran, 0);
  EXPECT_FALSE(runner.push([&](World&) { ran += 100; }));  // still full while the load parses
  release.set_value();
  for (int i = 0; i < 100 && !outcome; ++i) {
    runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::milliseconds(100));
    runner.apply_commands();
  }
  ASSERT_TRUE(outcome.has_value());
  EXPECT_TRUE(outcome->ok);
  EXPECT_EQ(ran, 2);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runner.push([&](World&) { ++ran; }));
  runner.apply_commands();
  EXPECT_EQ(ran, 5);
}

}  // namespace
}  // namespace macsim
