// The real robot's side, end to end without hardware: kurt_emulator (the KURT's microcontroller
// on the userspace CAN bus) + kurt_adapter (DDS) + the unchanged helloKurt, compared with the
// same helloKurt against macsim; the command timeout and the hard stop seen on the bus.
#include <gtest/gtest.h>
#include <signal.h>

#include <regex>
#include <set>
#include <sstream>

#include "macsim/client/supervisor_client.h"
#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

double monotonic_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The robot topic lines ("  rt/kurt/... (type, in|out)") a program printed at start.
std::set<std::string> robot_topics(const std::string& output) {
  std::set<std::string> topics;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("  rt/kurt/", 0) == 0) topics.insert(line);
  }
  return topics;
}

/// The emulator's log times (steady clock) of lines with exactly `what` after "t=SECONDS ".
std::vector<double> log_times(const std::string& log, const std::string& what) {
  std::vector<double> times;
  std::istringstream lines(log);
  const std::regex pattern("^t=([0-9.]+) (.*)$");
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, pattern) && m[2] == what) times.push_back(std::stod(m[1]));
  }
  return times;
}

/// kurt_emulator and kurt_adapter joined by a userspace CAN bus on two free loopback ports.
struct RealRobotSide {
  explicit RealRobotSide(int domain)
      : port(41000 + 2 * domain),
        emulator({bin("kurt_emulator"), "--can", udp(port, port + 1)}),
        adapter({bin("kurt_adapter"), "--can", udp(port + 1, port), "--domain",
                 std::to_string(domain)}) {
    EXPECT_TRUE(emulator.wait_for_output("kurt_emulator: on", 10s)) << emulator.output();
    EXPECT_TRUE(adapter.wait_for_output("rt/kurt/imu", 20s)) << adapter.output();
  }
  static std::string udp(int local, int peer) {
    return "udp:" + std::to_string(local) + ":" + std::to_string(peer);
  }
  int port;
  ChildProcess emulator, adapter;
};

TEST(KurtAdapter, TheSameHelloKurtReachesItsGoalOnTheSimulatorAndOnTheRealRobotSide) {
  std::set<std::string> sim_topics;
  {
    const int domain = unique_test_domain();
    ChildProcess macsim({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                         std::to_string(domain), "--cameras", "off"});
    ASSERT_TRUE(macsim.wait_for_output("stepping", 30s)) << macsim.output();
    ChildProcess controller({bin("helloKurt"), "--domain", std::to_string(domain)});
    EXPECT_EQ(controller.wait_for_exit(90s), 0) << controller.output();
    EXPECT_NE(controller.output().find("arrived"), std::string::npos) << controller.output();
    sim_topics = robot_topics(macsim.output());
  }
  const int domain = unique_test_domain();
  RealRobotSide robot(domain);
  ChildProcess controller({bin("helloKurt"), "--domain", std::to_string(domain)});
  EXPECT_EQ(controller.wait_for_exit(90s), 0) << controller.output() << robot.adapter.output();
  EXPECT_NE(controller.output().find("arrived"), std::string::npos) << controller.output();
  // The emulator's wheels really turned at helloKurt's cruise speed (30 cm/s, SPEED_CM).
  EXPECT_FALSE(log_times(robot.emulator.output(), "speed_cm 30 30").empty())
      << robot.emulator.output();
  // Every robot topic the adapter serves, macsim serves with the same name, type and direction.
  const auto real_topics = robot_topics(robot.adapter.output());
  ASSERT_GE(real_topics.size(), 8u) << robot.adapter.output();
  for (const auto& topic : real_topics) {
    EXPECT_TRUE(sim_topics.count(topic)) << topic << " is not served the same way by macsim";
  }
}

TEST(KurtAdapter, KillingTheControllerZeroesTheSpeedWithinTheCommandTimeout) {
  const int domain = unique_test_domain();
  RealRobotSide robot(domain);
  ChildProcess controller({bin("helloKurt"), "--domain", std::to_string(domain), "--distance", "50"});
  ASSERT_TRUE(robot.emulator.wait_for_output("speed_cm 30 30", 30s)) << robot.emulator.output();
  std::this_thread::sleep_for(300ms);  // cruising
  controller.signal(SIGKILL);
  const double killed = monotonic_now();
  ASSERT_TRUE(robot.emulator.wait_for_output("speed_cm 0 0", 5s)) << robot.emulator.output();
  const auto zero = log_times(robot.emulator.output(), "speed_cm 0 0");
  ASSERT_FALSE(zero.empty());
  const double delay = zero.back() - killed;
  std::printf("zero speed on the bus %.3f s after the controller was killed\n", delay);
  // The last command was sent before the kill: zero comes within the 0.6 s timeout plus one
  // 10 ms tick (and a little scheduling).
  EXPECT_LE(delay, 0.6 + 0.01 + 0.03);
  EXPECT_GT(delay, 0.3);  // and not before the timeout ran out: the robot was not stopped early
}

TEST(KurtAdapter, StoppingTheAdapterSendsAHardStopFirst) {
  for (int signal_number : {SIGTERM, SIGINT}) {
    const int domain = unique_test_domain();
    RealRobotSide robot(domain);
    ChildProcess controller({bin("helloKurt"), "--domain", std::to_string(domain), "--distance", "50"});
    ASSERT_TRUE(robot.emulator.wait_for_output("speed_cm 30 30", 30s)) << robot.emulator.output();
    const double stopped = monotonic_now();
    robot.adapter.signal(signal_number);
    EXPECT_EQ(robot.adapter.wait_for_exit(10s), 0) << robot.adapter.output();
    ASSERT_TRUE(robot.emulator.wait_for_output("HARD STOP", 5s)) << robot.emulator.output();
    const auto hard_stop = log_times(robot.emulator.output(), "HARD STOP");
    ASSERT_EQ(hard_stop.size(), 1u);
    EXPECT_GE(hard_stop[0], stopped);
    // Nothing drove the wheels after the hard stop (no speed command after it).
    const std::string log = robot.emulator.output();
    const std::string after = log.substr(log.find("HARD STOP"));
    EXPECT_EQ(after.find("speed_cm"), std::string::npos) << log;
    controller.signal(SIGTERM);
  }
}

TEST(KurtAdapter, AnswersTheFeaturesQueryAsARobotAndRefusesSimulationCommands) {
  const int domain = unique_test_domain();
  RealRobotSide robot(domain);
  namespace mm = macsim_msgs::msg::dds_;
  dds::Participant p({domain, "", "kurt_adapter_test"});
  client::SimulationClient sim(p);
  ASSERT_TRUE(sim.wait_for_server(20s));
  const auto features = sim.call(client::SimulationClient::request(mm::SIM_FEATURES));
  ASSERT_TRUE(features);
  EXPECT_EQ(features->code(), mm::ERR_OK);
  EXPECT_NE(features->features().find("robot"), std::string::npos) << features->features();
  EXPECT_EQ(features->features().find("simulator"), std::string::npos) << features->features();
  const auto pause = sim.call(client::SimulationClient::request(mm::SIM_PAUSE));
  ASSERT_TRUE(pause);
  EXPECT_EQ(pause->code(), mm::ERR_NOT_APPLICABLE);
  EXPECT_NE(pause->message().find("real robot"), std::string::npos) << pause->message();
}

TEST(KurtAdapter, ABusThatCannotBeOpenedIsAClearError) {
  ChildProcess adapter({bin("kurt_adapter"), "--can", "socketcan:nosuchcan7", "--domain",
                        std::to_string(unique_test_domain())});
  EXPECT_EQ(adapter.wait_for_exit(10s), 1);
  EXPECT_TRUE(adapter.output().find("no CAN support") != std::string::npos ||
              adapter.output().find("no CAN interface 'nosuchcan7'") != std::string::npos)
      << adapter.output();
}

}  // namespace
}  // namespace macsim::test
