// kurt_navigate end to end: against macsim in lock-step on clutter_field layouts, with a
// traverse model learned from the committed trial rows on the cloud's features. Judged from the
// simulator's world state by this test (support/clutter_judge.h): the robot's ground truth at
// the goal, a sphere or lying cylinder driven through, a box driven around. Bad arguments move
// nothing.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <set>

#include "macsim/client/supervisor_client.h"
#include "support/child_process.h"
#include "support/clutter_judge.h"
#include "support/test_domain.h"
#include "support/world_view.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;

struct NavigateRun {
  int exit_code = -1;
  std::string output;
  std::map<std::string, mm::Object_> before, after;
  std::vector<Eigen::Vector2d> path;  // the robot's middle, ground truth
};

std::string models_dir() {
  static TempDir dir("kurt_navigate_models_");
  static const bool made = [] {
    ChildProcess learn({bin("affordance_learn"), "--in",
                        source("tests/tools/affordances/traverse_trials.csv"), "--features",
                        "shape", "--save-model", dir.path()});
    EXPECT_EQ(learn.wait_for_exit(120s), 0) << learn.output();
    return true;
  }();
  (void)made;
  return dir.path();
}

/// macsim --lockstep on clutter_field --seed N and kurt_navigate stepping it, with `args`.
NavigateRun navigate(int seed, const std::vector<std::string>& args) {
  const std::string domain = std::to_string(unique_test_domain());
  ChildProcess macsim({bin("macsim"), "--world", source("worlds/clutter_field.xml"), "--domain",
                       domain, "--lockstep", "--seed", std::to_string(seed)});
  EXPECT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
  dds::Participant p({std::stoi(domain), "", "kurt_navigate_test"});
  WorldView view(p);
  NavigateRun run;
  // Where the clutter stands before the robot moves: the things of the field (a lock-step
  // simulator publishes the world's state after a step).
  client::SimulationClient simulation(p);
  EXPECT_TRUE(simulation.step(1).has_value()) << macsim.output();
  for (int i = 0; i < 1000; ++i) {
    run.before = view.snapshot();
    int clutter = 0;
    for (const auto& [name, o] : run.before) clutter += o.user_data() == "clutter";
    if (clutter == kClutterFieldThings) break;
    std::this_thread::sleep_for(10ms);
  }
  std::vector<std::string> argv{bin("kurt_navigate"), "--domain", domain, "--lockstep"};
  argv.insert(argv.end(), args.begin(), args.end());
  ChildProcess navigator(argv);
  run.exit_code = navigator.wait_for_exit(170s).value_or(-1);
  run.output = navigator.output();
  // In lock-step nothing moves once the controller stopped stepping: the last state stands.
  std::this_thread::sleep_for(500ms);
  run.after = view.snapshot();
  for (const auto& t : view.truth.all())
    run.path.emplace_back(t.pose().pose().position().x(), t.pose().pose().position().y());
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0) << macsim.output();
  return run;
}

/// Three layouts with the model: at the goal, into a sphere or a lying cylinder, around a box,
/// into no box or post. Of the layouts it crosses pushing something (over 50 it reaches the goal
/// on 46: bench_navigate, bench/README.md), the three it crosses soonest; the rate is the
/// benchmark's to measure.
class NavigateClutter : public ::testing::TestWithParam<int> {};

TEST_P(NavigateClutter, ReachesTheGoalPushingWhatRollsAndAroundWhatDoesNot) {
  const NavigateRun run = navigate(GetParam(), {"--affordances", models_dir()});
  const std::string what = "seed " + std::to_string(GetParam()) + "\n" + run.output;
  ASSERT_EQ(run.exit_code, 0) << what;
  EXPECT_NE(run.output.find("AT GOAL (policy model)"), std::string::npos) << what;
  ASSERT_FALSE(run.path.empty());
  EXPECT_LT((run.path.back() - Eigen::Vector2d(6, 0)).norm(), 0.6) << what;
  const ClutterJudgement judged(run.before, run.after, run.path);
  std::string through, around;
  for (const auto& n : judged.through) through += " " + n;
  for (const auto& n : judged.around) around += " " + n;
  EXPECT_TRUE(judged.any_of(judged.through, {"sphere_", "log_"}))
      << "pushed nothing that rolls; through:" << through << "\n"
      << what;
  EXPECT_TRUE(judged.any_of(judged.around, {"box_"})) << "around no box; around:" << around << "\n"
                                                      << what;
  EXPECT_FALSE(judged.any_of(judged.through, {"box_", "post_"}))
      << "drove into a box or a post; through:" << through << "\n"
      << what;
}

INSTANTIATE_TEST_SUITE_P(ThreeLayouts, NavigateClutter, ::testing::Values(28, 40, 49));

TEST(KurtNavigate, AnswersHelpAndRefusesBadArgumentsWithoutMovingAnything) {
  ChildProcess help({bin("kurt_navigate"), "--help"});
  EXPECT_EQ(help.wait_for_exit(10s), 0);
  EXPECT_NE(help.output().find("--policy"), std::string::npos) << help.output();
  const std::string models = models_dir();
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--policy", "avoid"},  // no domain
        {"--domain", "5"},                              // policy model without a model
        {"--domain", "5", "--policy", "random"},
        {"--domain", "5", "--policy", "avoid", "--goal", "nan,0"},
        {"--domain", "5", "--policy", "avoid", "--goal", "6"},
        {"--domain", "5", "--policy", "avoid", "--goal", "1e308,0"},
        {"--domain", "5", "--policy", "avoid", "--timeout", "-1"},
        {"--domain", "5", "--affordances", models + "/missing"}}) {
    std::vector<std::string> argv{bin("kurt_navigate")};
    argv.insert(argv.end(), bad.begin(), bad.end());
    ChildProcess p(argv);
    EXPECT_EQ(p.wait_for_exit(10s), 2) << bad.back() << "\n" << p.output();
  }
  // A traverse model on the cameras' features too: not what a cloud gives.
  TempDir dir("kurt_navigate_all_");
  ChildProcess learn({bin("affordance_learn"), "--in",
                      source("tests/tools/affordances/traverse_trials.csv"), "--save-model",
                      dir.path()});
  ASSERT_EQ(learn.wait_for_exit(120s), 0) << learn.output();
  ChildProcess all({bin("kurt_navigate"), "--domain", "5", "--affordances", dir.path()});
  EXPECT_EQ(all.wait_for_exit(10s), 2) << all.output();
  EXPECT_NE(all.output().find("--features shape"), std::string::npos) << all.output();
  // No robot: a clear message and its own exit code, after the discovery timeout.
  ChildProcess alone({bin("kurt_navigate"), "--domain", std::to_string(unique_test_domain()),
                      "--policy", "avoid", "--discovery-timeout", "1"});
  EXPECT_EQ(alone.wait_for_exit(30s), 3) << alone.output();
  EXPECT_NE(alone.output().find("no odometry"), std::string::npos) << alone.output();
}

}  // namespace
}  // namespace macsim::test
