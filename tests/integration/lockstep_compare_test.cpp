// Lock-step by contract: two lock-step runs of a controller on one seeded layout are the same
// run, record by record (macsim --compare A B): every step request names the commands it steps
// on, so nothing depends on when DDS delivered them or on the clients' random identities. A
// session with one command changed is told apart, naming that command.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "macsim/sim_core/session.h"
#include "support/child_process.h"
#include "support/demonstrator_run.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

/// macsim --compare A B: its exit code and what it said.
std::pair<int, std::string> compare(const std::string& a, const std::string& b) {
  ChildProcess p({bin("macsim"), "--compare", a, b});
  const int code = p.wait_for_exit(60s).value_or(-1);
  return {code, p.output()};
}

/// The session `from` with its first twist command driving 0.01 m/s faster, written to `to`;
/// the index (from 1) of the command changed.
std::size_t with_one_twist_changed(const std::string& from, const std::string& to) {
  Session s = read_session(from);
  for (std::size_t k = 0; k < s.commands.size(); ++k) {
    Command& c = s.commands[k].command;
    if (c.source != CommandSource::Robot || operation_name(c) != "twist" || !c.robot) continue;
    const auto v = c.robot->values();
    c = robot_command(c.target, robot::Twist{v[0] + 0.01, v[1]});
    write_session(to, s);
    return k + 1;
  }
  ADD_FAILURE() << from << " holds no twist";
  return 0;
}

/// Both runs the same, and the changed copy named where it parts.
void expect_same_runs(const std::string& dir) {
  const std::string a = dir + "/run1.session", b = dir + "/run2.session";
  const auto [same, said] = compare(a, b);
  EXPECT_EQ(same, 0) << said;
  EXPECT_NE(said.find("are the same run"), std::string::npos) << said;
  const std::size_t changed = with_one_twist_changed(a, dir + "/changed.session");
  const auto [differ, where] = compare(a, dir + "/changed.session");
  EXPECT_EQ(differ, 1) << where;
  EXPECT_NE(where.find("A command " + std::to_string(changed) + " at step"), std::string::npos)
      << where;
  // A file that is no session: a usage error naming it.
  const auto [bad, why] = compare(a, dir + "/missing.session");
  EXPECT_EQ(bad, 2) << why;
  EXPECT_NE(why.find("missing.session"), std::string::npos) << why;
}

TEST(LockstepCompare, TwoRunsOfTheDemonstratorAreTheSameRun) {
  TempDir dir("lockstep_compare_demo_");
  for (const char* run : {"run1", "run2"}) {
    const DemoRun played =
        play_demonstrator("kurt_demo", source("worlds/DemoWorld_v1.xml"), 5, {}, 170s,
                          {"--record-session", dir.path() + "/" + run + ".session"});
    // Each run is also one of the demonstrator's layouts, checked as KurtDemoSeeds checks its own.
    expect_through_the_door(played, std::string("layout 5, ") + run);
    if (::testing::Test::HasFatalFailure()) return;
  }
  expect_same_runs(dir.path());
}

TEST(LockstepCompare, TwoRunsOfTheNavigatorAreTheSameRun) {
  TempDir dir("lockstep_compare_navigate_");
  for (const char* run : {"run1", "run2"}) {
    const std::string domain = std::to_string(unique_test_domain());
    ChildProcess macsim({bin("macsim"), "--world", source("worlds/clutter_field.xml"), "--domain",
                         domain, "--lockstep", "--seed", "28", "--record-session",
                         dir.path() + "/" + run + ".session"});
    ASSERT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
    // Avoiding everything for 20 s of robot time: the comparison, not the goal, is the point.
    ChildProcess navigator({bin("kurt_navigate"), "--domain", domain, "--lockstep", "--policy",
                            "avoid", "--timeout", "20"});
    const int code = navigator.wait_for_exit(120s).value_or(-1);
    EXPECT_TRUE(code == 0 || code == 4 || code == 7) << navigator.output();
    macsim.signal(SIGTERM);
    EXPECT_EQ(macsim.wait_for_exit(10s), 0) << macsim.output();
  }
  expect_same_runs(dir.path());
}

}  // namespace
}  // namespace macsim::test
