// learn_effects end to end: an exploration episode against macsim in lock-step write trials and a
// domain that reads back; the domain learned from the committed rows (--from-trials, no episodes)
// is one kurt_plan plans over to reach the demonstrator's door, judged from the world state.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "macsim/affordances/effects.h"
#include "macsim/affordances/pddl.h"
#include "support/demonstrator_run.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace af = macsim::affordances;

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(LearnEffects, AnEpisodeWritesTrialsAndADomainThatReadsBack) {
  TempDir dir("learn_effects_");
  ChildProcess learn({bin("learn_effects"), "--domain", std::to_string(unique_test_domain()),
                      "--out", dir.path(), "--seed", "2", "--episodes", "1", "--instances", "1",
                      "--steps", "4"});
  ASSERT_EQ(learn.wait_for_exit(150s), 0) << learn.output();
  EXPECT_NE(learn.output().find("1 episode(s), 0 failed"), std::string::npos) << learn.output();
  const auto trials = af::read_effect_trials(read(dir.path() + "/trials.csv"), "trials.csv");
  ASSERT_FALSE(trials.empty());
  EXPECT_EQ(trials[0].behaviour, "go");  // every episode goes somewhere first
  const auto domain = af::pddl::load_domain(dir.path() + "/effects.ppddl");
  EXPECT_FALSE(domain.operators.empty());
  EXPECT_NO_THROW(af::pddl::load_domain(dir.path() + "/effects.pddl"));
  EXPECT_NO_THROW(af::load_thresholds(dir.path() + "/thresholds.yml"));
  EXPECT_NE(read(dir.path() + "/report.txt").find("go: "), std::string::npos);
}

TEST(LearnEffects, KurtPlanReachesTheDoorOverTheDomainLearnedFromTheCommittedRows) {
  TempDir dir("learn_effects_rows_");
  ChildProcess learn({bin("learn_effects"), "--domain", std::to_string(unique_test_domain()),
                      "--out", dir.path(), "--from-trials",
                      source("tests/affordances/effect_trials.csv")});
  ASSERT_EQ(learn.wait_for_exit(60s), 0) << learn.output();
  const DemoRun run = play_demonstrator("kurt_plan", source("worlds/DemoWorld_v1.xml"), 4,
                                        {"--affordances", dir.path()});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("goal reached: yes"), std::string::npos) << run.output;
  ASSERT_NE(can_on_platform(run), nullptr) << run.output;
  ASSERT_TRUE(run.truth.has_value());
  EXPECT_GT(run.truth->pose().pose().position().x(), 1.5 + 0.3);
}

TEST(LearnEffects, BadArgumentsAndBadRowsAreRefused) {
  TempDir dir("learn_effects_args_");
  ChildProcess none({bin("learn_effects"), "--out", dir.path()});
  EXPECT_EQ(none.wait_for_exit(10s), 2) << none.output();
  ChildProcess episodes({bin("learn_effects"), "--domain", "5", "--out", dir.path(), "--episodes", "0"});
  EXPECT_EQ(episodes.wait_for_exit(10s), 2) << episodes.output();
  ChildProcess world({bin("learn_effects"), "--domain", "5", "--out", dir.path(), "--world",
                      dir.path() + "/none.xml"});
  EXPECT_EQ(world.wait_for_exit(10s), 2) << world.output();
  EXPECT_NE(world.output().find(dir.path() + "/none.xml: no such world file"), std::string::npos)
      << world.output();
  af::pddl::save_text(dir.path() + "/bad.csv", "behaviour,parameters\n");
  ChildProcess bad({bin("learn_effects"), "--domain", "5", "--out", dir.path(), "--from-trials",
                    dir.path() + "/bad.csv"});
  EXPECT_EQ(bad.wait_for_exit(10s), 2) << bad.output();
  EXPECT_NE(bad.output().find(dir.path() + "/bad.csv:1: not a file of effect trials"),
            std::string::npos)
      << bad.output();
}

}  // namespace
}  // namespace macsim::test
