// affordance_trials against real lock-step simulators: the rows do not depend on how many
// instances ran them (lift, push, climb, stack, traverse), a trial repeats bit for bit under CPU
// load with the state hash checked after every step, a killed run resumes without losing or
// repeating a row, an instance killed mid-run is noticed and its trials run elsewhere, a
// simulator of the run that died is started again and its trial played again; the
// committed rows are what the trials make today;
// affordance_learn learns from the rows and draws its plots; bad arguments start nothing.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// A row without its instance and wall time (the last two columns): what must repeat.
std::string result_part(const std::string& row) {
  auto cut = row.rfind(',');
  cut = row.rfind(',', cut - 1);
  return row.substr(0, cut);
}

/// Affordance, generator and seed: the trial a row is of.
std::string key_of(const std::string& row) {
  std::size_t comma = 0;
  for (int i = 0; i < 3; ++i) comma = row.find(',', comma + 1);
  return row.substr(0, comma);
}

std::vector<std::string> results(const std::string& path) {
  std::vector<std::string> out;
  for (const auto& line : lines_of(path)) out.push_back(result_part(line));
  return out;
}

/// Simulators of the trial world this test starts itself, on consecutive domains.
struct Simulators {
  explicit Simulators(int count) : first(unique_test_domains(count)) {
    for (int i = 0; i < count; ++i) {
      processes.push_back(std::make_unique<ChildProcess>(std::vector<std::string>{
          bin("macsim"), "--world", source("worlds/affordance_trials.xml"), "--domain",
          std::to_string(first + i), "--lockstep", "--camera-rate", "1.25"}));
    }
  }
  std::string domains() const {
    std::string list;
    for (std::size_t i = 0; i < processes.size(); ++i)
      list += (i ? "," : "") + std::to_string(first + static_cast<int>(i));
    return list;
  }
  int first;
  std::vector<std::unique_ptr<ChildProcess>> processes;
};

int run(std::vector<std::string> argv, std::string* output = nullptr,
        std::chrono::milliseconds timeout = 170s) {
  ChildProcess p(std::move(argv));
  const auto code = p.wait_for_exit(timeout);
  if (output) *output = p.output();
  return code.value_or(-1);
}

/// The rows file has a header and a row of each of `trials` trials, none twice.
void expect_each_trial_once(const std::string& csv, std::size_t trials, const std::string& output) {
  const auto rows = lines_of(csv);
  ASSERT_EQ(rows.size(), trials + 1) << output;
  std::set<std::string> keys;
  for (std::size_t i = 1; i < rows.size(); ++i) keys.insert(key_of(rows[i]));
  EXPECT_EQ(keys.size(), trials);
}

class ByAffordance : public ::testing::TestWithParam<const char*> {};

TEST_P(ByAffordance, OneInstanceAndThreeGiveTheSameRows) {
  TempDir dir("affordance_k_");
  const std::string affordance = GetParam();
  // One simulator started by the runner, then three running ones it attaches to.
  std::string out1, out3;
  ASSERT_EQ(run({bin("affordance_trials"), "--domain", std::to_string(unique_test_domain()),
                 "--affordance", affordance, "--trials", "9", "--seed", "11", "--out",
                 dir.path() + "/k1.csv", "--logs", dir.path()},
                &out1),
            0)
      << out1;
  Simulators three(3);
  ASSERT_EQ(run({bin("affordance_trials"), "--attach", three.domains(), "--affordance", affordance,
                 "--trials", "9", "--seed", "11", "--out", dir.path() + "/k3.csv"},
                &out3),
            0)
      << out3;
  const auto k1 = results(dir.path() + "/k1.csv"), k3 = results(dir.path() + "/k3.csv");
  ASSERT_EQ(k1.size(), 10u);  // header and nine rows
  EXPECT_EQ(k1, k3);
  // The three instances shared the work.
  std::set<std::string> instances;
  for (const auto& line : lines_of(dir.path() + "/k3.csv")) {
    const auto tail = line.substr(result_part(line).size() + 1);
    instances.insert(tail.substr(0, tail.find(',')));
  }
  EXPECT_GE(instances.size(), 3u) << out3;  // the header's "instance" and at least two ids
  // Every row has its affordance and a label of that affordance.
  const std::map<std::string, std::set<std::string>> labels{
      {"lift", {"liftable", "not_liftable"}},
      {"push", {"pushed", "rolled", "stalled"}},
      {"climb", {"climbed", "slid_back", "stalled"}},
      {"stack", {"stacked", "slid_off", "toppled"}},
      {"traverse", {"traversable", "not_traversable"}}};
  for (std::size_t i = 1; i < k1.size(); ++i) {
    std::stringstream row(k1[i]);
    std::string a, g, seed, label;
    std::getline(row, a, ',');
    std::getline(row, g, ',');
    std::getline(row, seed, ',');
    std::getline(row, label, ',');
    EXPECT_EQ(a, affordance);
    EXPECT_EQ(seed, std::to_string(10 + i));
    EXPECT_TRUE(labels.at(affordance).count(label)) << k1[i];
  }
}

INSTANTIATE_TEST_SUITE_P(Affordances, ByAffordance,
                         ::testing::Values("lift", "push", "climb", "stack", "traverse"));

/// The committed rows (tests/tools/affordances/) and how they were made.
struct CommittedRows {
  const char* affordance;
  const char* generator;
};

class CommittedRowsTest : public ::testing::TestWithParam<CommittedRows> {};

TEST_P(CommittedRowsTest, AreWhatTheTrialsMakeToday) {
  // Models of these rows judge what a controller perceives today: a change to the simulator or
  // the perception that moves a feature must regenerate them (affordance_trials --affordance A
  // --generator G --trials 300, or 200 for traverse).
  const auto [affordance, generator] = GetParam();
  const std::string file =
      source("tests/tools/affordances/" + std::string(affordance) + "_trials.csv");
  std::map<std::string, std::string> committed;  // by trial: its row
  for (const auto& line : lines_of(file)) committed[key_of(line)] = result_part(line);
  TempDir dir("affordance_rows_");
  std::string out;
  ASSERT_EQ(run({bin("affordance_trials"), "--domain", std::to_string(unique_test_domain()),
                 "--affordance", affordance, "--generator", generator, "--trials", "3", "--out",
                 dir.path() + "/today.csv"},
                &out),
            0)
      << out;
  const auto today = lines_of(dir.path() + "/today.csv");
  ASSERT_EQ(today.size(), 4u);
  EXPECT_EQ(result_part(today[0]), committed[key_of(lines_of(file)[0])]) << "the columns";
  for (std::size_t i = 1; i < today.size(); ++i) {
    ASSERT_TRUE(committed.count(key_of(today[i]))) << today[i];
    EXPECT_EQ(result_part(today[i]), committed[key_of(today[i])])
        << file << " is out of date: regenerate it";
  }
}

INSTANTIATE_TEST_SUITE_P(Fixtures, CommittedRowsTest,
                         ::testing::Values(CommittedRows{"lift", "material"},
                                           CommittedRows{"stack", "balanced"},
                                           CommittedRows{"traverse", "balanced"}),
                         [](const auto& test) { return std::string(test.param.affordance); });

TEST(AffordanceTrials, ATrialRepeatsBitForBitUnderLoadWithEveryStepHashed) {
  // Two busy loops keep both cores loaded while two instances run the same trial 20 times,
  // one step per request: every state hash of every repeat goes into the row's trace.
  ChildProcess hog1({"/bin/sh", "-c", "while :; do :; done"});
  ChildProcess hog2({"/bin/sh", "-c", "while :; do :; done"});
  Simulators two(2);
  TempDir dir("affordance_repeat_");
  std::string output;
  ASSERT_EQ(run({bin("affordance_trials"), "--attach", two.domains(), "--trials", "1", "--seed",
                 "4", "--repeat", "20", "--hash-every-step", "--out", dir.path() + "/r.csv"},
                &output),
            0)
      << output;
  EXPECT_NE(output.find("repeats identical: 20 of 20"), std::string::npos) << output;
  EXPECT_EQ(lines_of(dir.path() + "/r.csv").size(), 2u);
}

TEST(AffordanceTrials, AKilledRunResumesWithoutLosingOrRepeatingARow) {
  TempDir dir("affordance_resume_");
  const std::string csv = dir.path() + "/rows.csv";
  const std::string domain = std::to_string(unique_test_domain());
  const std::vector<std::string> command{bin("affordance_trials"),
                                         "--domain",
                                         domain,
                                         "--trials",
                                         "24",
                                         "--seed",
                                         "11",
                                         "--out",
                                         csv,
                                         "--logs",
                                         dir.path()};
  {
    ChildProcess first(command);
    // Killed (no chance to tidy up) once a few rows are in.
    for (int i = 0; i < 600 && lines_of(csv).size() < 5; ++i) std::this_thread::sleep_for(50ms);
    ASSERT_GE(lines_of(csv).size(), 5u) << first.output();
    first.signal(SIGKILL);
    first.wait_for_exit(10s);
  }
  const std::size_t before = lines_of(csv).size() - 1;
  ASSERT_LT(before, 24u) << "the run finished before it was killed";
  // The simulator it started is gone with it? Not necessarily: the runner was SIGKILLed.
  std::string output;
  ASSERT_EQ(run(command, &output), 0) << output;
  EXPECT_NE(output.find(std::to_string(before) + " trials already in"), std::string::npos)
      << output;
  const auto rows = lines_of(csv);
  ASSERT_EQ(rows.size(), 25u);
  std::set<std::string> seeds;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    std::stringstream row(rows[i]);
    std::string a, g, seed;
    std::getline(row, a, ',');
    std::getline(row, g, ',');
    std::getline(row, seed, ',');
    EXPECT_EQ(seed, std::to_string(10 + i)) << "sorted by seed";
    seeds.insert(seed);
  }
  EXPECT_EQ(seeds.size(), 24u);
  // A third run has nothing left to do.
  ASSERT_EQ(run(command, &output), 0) << output;
  EXPECT_NE(output.find("24 trials already in"), std::string::npos) << output;
  EXPECT_EQ(lines_of(csv), rows);
}

TEST(AffordanceTrials, AnInstanceKilledMidRunIsNoticedAndItsTrialsRunElsewhere) {
  Simulators two(2);
  TempDir dir("affordance_lost_");
  const std::string csv = dir.path() + "/rows.csv";
  ChildProcess runner({bin("affordance_trials"), "--attach", two.domains(), "--trials", "20",
                       "--seed", "11", "--timeout", "3", "--out", csv});
  for (int i = 0; i < 600 && lines_of(csv).size() < 4; ++i) std::this_thread::sleep_for(50ms);
  ASSERT_GE(lines_of(csv).size(), 4u) << runner.output();
  two.processes[1]->signal(SIGKILL);
  const auto code = runner.wait_for_exit(170s);
  ASSERT_EQ(code, 0) << runner.output();
  EXPECT_NE(runner.output().find("instance 1 (domain " + std::to_string(two.first + 1) + "): lost"),
            std::string::npos)
      << runner.output();
  EXPECT_NE(runner.output().find("1 instance(s) lost"), std::string::npos) << runner.output();
  expect_each_trial_once(csv, 20, runner.output());
}

/// The children of process `pid` (of any of its threads).
std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> found;
  for (const auto& task :
       std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task")) {
    std::ifstream in(task.path() / "children");
    for (pid_t child = 0; in >> child;) found.push_back(child);
  }
  return found;
}

TEST(AffordanceTrials, ASimulatorOfTheRunLostWhileItStillRunsIsConnectedToAgain) {
  // Stopped (as a starved process looks) until the runner calls it lost, and 2 s more: once it
  // goes on, the runner connects to it again.
  TempDir dir("affordance_reconnect_");
  const std::string csv = dir.path() + "/rows.csv";
  ChildProcess runner({bin("affordance_trials"), "--domain", std::to_string(unique_test_domain()),
                       "--instances", "1", "--trials", "6", "--seed", "11", "--timeout", "2",
                       "--out", csv});
  for (int i = 0; i < 1200 && lines_of(csv).size() < 3; ++i) std::this_thread::sleep_for(50ms);
  ASSERT_GE(lines_of(csv).size(), 3u) << runner.output();
  const auto simulators = children_of(runner.pid());
  ASSERT_EQ(simulators.size(), 1u) << runner.output();
  ASSERT_EQ(::kill(simulators[0], SIGSTOP), 0);
  ASSERT_TRUE(runner.wait_for_output("connecting again", 30s)) << runner.output();
  std::this_thread::sleep_for(2s);
  ASSERT_EQ(::kill(simulators[0], SIGCONT), 0);
  ASSERT_EQ(runner.wait_for_exit(120s), 0) << runner.output();
  EXPECT_NE(runner.output().find("1 reconnection(s)"), std::string::npos) << runner.output();
  expect_each_trial_once(csv, 6, runner.output());
}

// A simulator the run started whose process died (the Slurm array's one instance, or one of
// several) is started again and the trial under way plays again from its reset: the rows equal
// those of a run never killed, the committed lift rows (CommittedRowsTest keeps them current).
TEST(AffordanceTrials, ASimulatorOfTheRunThatDiedIsStartedAgainAndTheRowsEqualARunNeverKilled) {
  TempDir dir("affordance_restart_");
  const std::string committed_file = source("tests/tools/affordances/lift_trials.csv");
  std::map<std::string, std::string> never_killed;  // by trial: its row
  for (const auto& line : lines_of(committed_file)) never_killed[key_of(line)] = result_part(line);
  constexpr int kTrials = 5;
  for (const int instances : {1, 2}) {
    const std::string csv = dir.path() + "/killed_" + std::to_string(instances) + ".csv";
    ChildProcess runner({bin("affordance_trials"), "--domain",
                         std::to_string(unique_test_domains(instances)), "--instances",
                         std::to_string(instances), "--affordance", "lift", "--generator",
                         "material", "--trials", std::to_string(kTrials), "--timeout", "2",
                         "--out", csv});
    for (int i = 0; i < 1200 && lines_of(csv).size() < 3; ++i) std::this_thread::sleep_for(50ms);
    ASSERT_GE(lines_of(csv).size(), 3u) << runner.output();
    const auto simulators = children_of(runner.pid());
    ASSERT_EQ(simulators.size(), std::size_t(instances)) << runner.output();
    ASSERT_EQ(::kill(simulators[0], SIGKILL), 0);
    ASSERT_EQ(runner.wait_for_exit(120s), 0) << runner.output();
    EXPECT_NE(runner.output().find("starting its simulator again (1 of 3)"), std::string::npos)
        << runner.output();
    EXPECT_NE(runner.output().find("1 simulator(s) started again after they died"),
              std::string::npos)
        << runner.output();
    EXPECT_EQ(runner.output().find("instance(s) lost"), std::string::npos) << runner.output();
    const auto rows = lines_of(csv);
    ASSERT_EQ(rows.size(), std::size_t(kTrials + 1)) << runner.output();
    EXPECT_EQ(result_part(rows[0]), never_killed[key_of(lines_of(committed_file)[0])]);
    for (std::size_t i = 1; i < rows.size(); ++i) {
      ASSERT_TRUE(never_killed.count(key_of(rows[i]))) << rows[i];
      EXPECT_EQ(result_part(rows[i]), never_killed[key_of(rows[i])])
          << instances << " instance(s)\n" << runner.output();
    }
  }
}

TEST(AffordanceLearn, LearnsFromTrialRowsAndDrawsItsPlots) {
  TempDir dir("affordance_learn_");
  std::string output;
  ASSERT_EQ(run({bin("affordance_learn"), "--in", source("tests/tools/affordances/lift_trials.csv"),
                 "--out", dir.path() + "/plots", "--min-accuracy", "0.95"},
                &output),
            0)
      << output;
  EXPECT_NE(output.find("lift: 300 trials"), std::string::npos) << output;
  EXPECT_NE(output.find("true \\ predicted"), std::string::npos) << output;
  for (const char* png : {"/plots/lift_learning_curve.png", "/plots/lift_scatter.png"})
    EXPECT_GT(std::filesystem::file_size(dir.path() + png), 2000u) << png;
  // --save-model: the model file a controller loads, refit on every row.
  ASSERT_EQ(run({bin("affordance_learn"), "--in", source("tests/tools/affordances/lift_trials.csv"),
                 "--save-model", dir.path() + "/models"},
                &output),
            0)
      << output;
  EXPECT_NE(output.find("model: " + dir.path() + "/models/lift.yml"), std::string::npos) << output;
  EXPECT_NE(output.find("refit on all 300 rows"), std::string::npos) << output;
  EXPECT_GT(std::filesystem::file_size(dir.path() + "/models/lift.yml"), 10000u);
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/models/lift_scatter.png"));
  // An accuracy it cannot reach is an exit 1; rows it cannot read an exit 2 naming the file.
  EXPECT_EQ(
      run({bin("affordance_learn"), "--in", source("tests/tools/affordances/lift_trials.csv"),
           "--out", dir.path() + "/plots", "--features", "laser_range", "--min-accuracy", "1.01"}),
      1);
  std::ofstream(dir.path() + "/bad.csv") << "affordance,seed,label\nlift,1\n";
  EXPECT_EQ(
      run({bin("affordance_learn"), "--in", dir.path() + "/bad.csv", "--out", dir.path()}, &output),
      2);
  EXPECT_NE(output.find("bad.csv:2"), std::string::npos) << output;
}

TEST(AffordanceTrials, AnswersHelpAndRefusesBadArgumentsWithoutStartingAnything) {
  std::string output;
  EXPECT_EQ(run({bin("affordance_trials"), "--help"}, &output, 10s), 0);
  EXPECT_NE(output.find("--instances"), std::string::npos);
  EXPECT_EQ(run({bin("affordance_learn"), "--help"}, &output, 10s), 0);
  TempDir dir("affordance_args_");
  const std::string csv = dir.path() + "/x.csv";
  // No domain: no simulator is started and no file written.
  EXPECT_EQ(run({bin("affordance_trials"), "--out", csv}, &output, 10s), 2);
  EXPECT_NE(output.find("--domain"), std::string::npos) << output;
  EXPECT_EQ(run({bin("affordance_trials"), "--domain", "150", "--affordance", "fly", "--out", csv},
                &output, 10s),
            2);
  EXPECT_NE(output.find("fly"), std::string::npos) << output;
  EXPECT_EQ(run({bin("affordance_trials"), "--domain", "150", "--trials", "0", "--out", csv},
                nullptr, 10s),
            2);
  EXPECT_EQ(run({bin("affordance_trials"), "--attach", "1,x", "--out", csv}, nullptr, 10s), 2);
  EXPECT_FALSE(std::filesystem::exists(csv));
}

}  // namespace
}  // namespace macsim::test
