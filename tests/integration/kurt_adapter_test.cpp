// The real robot's side, end to end without hardware: kurt_emulator (the KURT's microcontroller
// on the userspace CAN bus) + kurt_adapter (DDS) + the unchanged helloKurt, compared with the
// same helloKurt against macsim; the command timeout and the hard stop seen on the bus.
#include <gtest/gtest.h>
#include <signal.h>

#include <regex>
#include <set>
#include <sstream>

#include "macsim/client/supervisor_client.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"
#include "support/child_process.h"
#include "support/latest_sample.h"
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
  explicit RealRobotSide(int domain, std::vector<std::string> emulator_options = {})
      : port(5000 + 2 * domain),  // below Fast DDS ports (7400 + 250 d) and ephemeral ones
        emulator(with({bin("kurt_emulator"), "--can", udp(port, port + 1)}, emulator_options)),
        adapter({bin("kurt_adapter"), "--can", udp(port + 1, port), "--domain",
                 std::to_string(domain)}) {
    EXPECT_TRUE(emulator.wait_for_output("kurt_emulator: on", 10s)) << emulator.output();
    EXPECT_TRUE(adapter.wait_for_output("rt/kurt/imu", 20s)) << adapter.output();
  }
  static std::vector<std::string> with(std::vector<std::string> argv,
                                       const std::vector<std::string>& more) {
    argv.insert(argv.end(), more.begin(), more.end());
    return argv;
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
  ChildProcess controller(
      {bin("helloKurt"), "--domain", std::to_string(domain), "--distance", "50"});
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
  // 10 ms tick, plus scheduling on a loaded CI machine (measured here: 0.59-0.61 s).
  EXPECT_LE(delay, 0.6 + 0.01 + 0.09);
  EXPECT_GT(delay, 0.3);  // and not before the timeout ran out: the robot was not stopped early
}

TEST(KurtAdapter, StoppingTheAdapterSendsAHardStopFirst) {
  for (int signal_number : {SIGTERM, SIGINT}) {
    const int domain = unique_test_domain();
    RealRobotSide robot(domain);
    ChildProcess controller(
        {bin("helloKurt"), "--domain", std::to_string(domain), "--distance", "50"});
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

TEST(KurtAdapter, PublishesRangesImuAndRotunitAndSwitchesTheMagnetActuator) {
  namespace sm = sensor_msgs::msg::dds_;
  const int domain = unique_test_domain();
  RealRobotSide robot(domain, {"--range", "0.3", "--sensor-range", "ultrasound_front=0.6",
                               "--sensor-range", "ir_back=2.0"});
  dds::Participant p({domain, "", "kurt_adapter_test"});
  Samples<sm::Range_PubSubType> ranges(p, dds::topics::range("kurt"));
  Samples<sm::Imu_PubSubType> imu(p, dds::topics::imu("kurt"));
  Samples<sm::JointState_PubSubType> joints(p, dds::topics::joint_states("kurt"));
  // Ranges in the frames and limits macsim uses; the emulator's distances come back in whole
  // cm through the ADC curves; 2 m is beyond the IR's reach: invalid (-0.01).
  auto sonar = ranges.wait_for(
      [](const auto& r) { return r.header().frame_id() == "ultrasound_front"; }, 20s);
  ASSERT_TRUE(sonar);
  EXPECT_NEAR(sonar->range(), 0.6, 0.011);
  EXPECT_EQ(sonar->radiation_type(), 0);  // ultrasound
  EXPECT_FLOAT_EQ(sonar->max_range(), 1.0f);
  auto left = ranges.wait_for([](const auto& r) { return r.header().frame_id() == "ir_left"; }, 5s);
  ASSERT_TRUE(left);
  EXPECT_NEAR(left->range(), 0.3, 0.011);
  auto back = ranges.wait_for([](const auto& r) { return r.header().frame_id() == "ir_back"; }, 5s);
  ASSERT_TRUE(back);
  EXPECT_FLOAT_EQ(back->range(), -0.01f);

  // Turning in place: the gyro (after its first 100 frames) reports a counter-clockwise yaw.
  dds::Writer<geometry_msgs::msg::dds_::Twist_PubSubType> cmd_vel(p, dds::topics::cmd_vel("kurt"),
                                                                  dds::QosFamily::Command);
  dds::Writer<geometry_msgs::msg::dds_::Twist_PubSubType> rot_vel(p, dds::topics::rot_vel("kurt"),
                                                                  dds::QosFamily::Command);
  dds::Writer<kurt_msgs::msg::dds_::MagnetCommand_PubSubType> magnet(
      p, dds::topics::crane_magnet("kurt"), dds::QosFamily::Command);
  std::optional<sm::Imu_> turned;
  std::optional<sm::JointState_> rotunit;
  kurt_msgs::msg::dds_::MagnetCommand_ on;
  on.on(true);
  for (int i = 0; i < 60 && (!turned || !rotunit); ++i) {
    cmd_vel.write(dds::planar_twist(0.0, 0.8));
    rot_vel.write(dds::planar_twist(0.0, M_PI / 6));
    magnet.write(on);
    turned = imu.wait_for([](const auto& m) { return dds::yaw_of(m.orientation()) > 0.2; }, 100ms);
    rotunit = joints.wait_for(
        [](const auto& j) { return j.name().size() == 1 && j.position()[0] > 0.05; }, 100ms);
  }
  ASSERT_TRUE(turned) << "no yaw on rt/kurt/imu";
  EXPECT_EQ(turned->header().frame_id(), "base_link");
  ASSERT_TRUE(rotunit) << "laser_rot_joint never turned";
  EXPECT_EQ(rotunit->name()[0], "laser_rot_joint");
  EXPECT_DOUBLE_EQ(rotunit->velocity()[0], 42 * 2 * M_PI * 20 / 10240);  // quantized as sent
  // The magnet's command reached the bus as the actuator output.
  EXPECT_TRUE(robot.emulator.wait_for_output("actuator on", 5s)) << robot.emulator.output();
}

TEST(KurtAdapter, AnswersTheFeaturesQueryAsARobotAndLeavesSimulationCommandsAlone) {
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
  // Everything else is left to a simulator (none here): no answer from the robot.
  EXPECT_FALSE(sim.call(client::SimulationClient::request(mm::SIM_PAUSE), 1s));
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
