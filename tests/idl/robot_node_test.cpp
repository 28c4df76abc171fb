// The robot node over real DDS (two participants in this process, discovering each other
// through shared memory as two processes would, so a loaded machine may take seconds): it serves a mock robot's
// topics, hands commands to the owner's queue (dropping numbers that are not finite), publishes
// readings, and serves only what the robot has.
#include "macsim/robot/robot_node.h"

#include <gtest/gtest.h>

#include <thread>

#include "macsim/client/robot_client.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"
#include "macsim/msg/std_msgsPubSubTypes.h"
#include "macsim/robot/command_queue.h"
#include "macsim/robot/mock_robot.h"
#include "support/child_process.h"
#include "support/latest_sample.h"
#include "support/nudge_command.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace gm = geometry_msgs::msg::dds_;
namespace sm = sensor_msgs::msg::dds_;
namespace km = kurt_msgs::msg::dds_;

robot::Capabilities rover() {
  robot::Capabilities c;
  c.ranges = c.imu = c.rotunit = c.magnet = true;  // the real KURT's: no crane, laser, truth
  return c;
}

struct Served {
  int domain = unique_test_domain();
  dds::Participant robot_side{{domain, source("deploy/dds/localhost.xml"), "robot"}};
  dds::Participant controller_side{{domain, source("deploy/dds/localhost.xml"), "controller"}};
  robot::MockRobot mock{"kurt", rover()};
  BasicCommandQueue<robot::RobotInterface&> queue;
  robot::RobotNode node{robot_side, mock, [this](robot::RobotCommand c, const dds::SampleId&) {
                          queue.push([c](robot::RobotInterface& r) { r.execute(c); });
                        }};

  /// The owner's loop for `seconds`: commands, then time, then readings, every 10 ms.
  void run(double seconds) {
    for (int i = 0; i < static_cast<int>(seconds * 100); ++i) {
      node.poll_commands();
      queue.drain(mock);
      now += 0.01;
      mock.advance(now);
      node.publish();
      std::this_thread::sleep_for(10ms);
    }
  }
  double now = 0;
};

TEST(RobotNode, ServesAMockRobotCommandsInReadingsOut) {
  Served s;
  s.mock.set_ranges({{"ir_left", false, 0.3}, {"ultrasound_front", true, 0.7}});
  client::RobotClient controller(s.controller_side, "kurt");
  Samples<sm::Range_PubSubType> ranges(s.controller_side, dds::topics::range("kurt"));
  for (int i = 0; i < 3000 && !controller.commander_matched(); ++i)
    std::this_thread::sleep_for(10ms);
  ASSERT_TRUE(controller.commander_matched());
  controller.drive(std::nan(""), 0.0);  // dropped by the node, never reaches the robot
  controller.drive(0.5, 0.0);
  ASSERT_TRUE(controller.wait_delivered(2s));
  s.run(1.0);
  const auto odom = controller.wait_for_odometry(2s);
  ASSERT_TRUE(odom.has_value());
  EXPECT_NEAR(odom->pose().pose().position().x(), 0.5 * 0.6, 0.02);  // until the 0.6 s timeout
  EXPECT_TRUE(std::isfinite(odom->pose().pose().position().y()));
  const auto sonar = ranges.wait_for(
      [](const sm::Range_& r) { return r.header().frame_id() == "ultrasound_front"; }, 2s);
  ASSERT_TRUE(sonar.has_value());
  EXPECT_NEAR(sonar->range(), 0.7, 1e-6);
}

TEST(RobotNode, PrimedItKnowsTheRobotsReadingsAndWritesNone) {
  // A simulator resumed from a session: what the robot has went out before the kill.
  Served s;
  client::RobotClient controller(s.controller_side, "kurt");
  for (int i = 0; i < 3000 && !controller.odometry_writers_seen(); ++i)
    std::this_thread::sleep_for(10ms);
  ASSERT_GT(controller.odometry_writers_seen(), 0);
  s.mock.advance(0.5);
  EXPECT_FALSE(s.node.latest().odometry.has_value());
  s.node.prime();
  EXPECT_TRUE(s.node.latest().odometry.has_value());
  EXPECT_FALSE(controller.wait_for_odometry(500ms).has_value());
  s.node.publish();  // the readings since: none new, but a publish writes what it reads
  s.mock.advance(0.6);
  s.node.publish();
  EXPECT_TRUE(controller.wait_for_odometry(2s).has_value());
}

TEST(RobotNode, ServesWhatTheRobotHasAndNamesWhatItLacks) {
  Served s;
  const auto lines = s.node.topic_lines();
  auto served = [&](const std::string& topic) {
    for (const auto& l : lines) {
      if (l.rfind(topic + " (", 0) == 0) return true;
    }
    return false;
  };
  EXPECT_TRUE(served("rt/kurt/cmd_vel"));
  EXPECT_TRUE(served("rt/kurt/odom"));
  EXPECT_TRUE(served("rt/kurt/rot_vel"));
  EXPECT_TRUE(served("rt/kurt/crane/magnet"));
  EXPECT_FALSE(served("rt/kurt/crane/command"));
  EXPECT_FALSE(served("rt/kurt/ground_truth"));
  const auto lacking = s.node.lacking_topics();
  // The mock has no description either: no rt/kurt/robot_description.
  EXPECT_EQ(lacking, (std::vector<std::string>{"rt/kurt/crane/command", "rt/kurt/ground_truth",
                                               "rt/kurt/scan360", "rt/kurt/points",
                                               "rt/kurt/crane/state",
                                               "rt/kurt/robot_description"}));
}

TEST(RobotNode, CraneCommandsReachARobotWithACrane) {
  Served s;
  robot::Capabilities full = rover();
  full.crane = true;
  robot::MockRobot crane_robot("arm", full);
  BasicCommandQueue<robot::RobotInterface&> queue;
  robot::RobotNode node(s.robot_side, crane_robot,
                        [&](robot::RobotCommand c, const dds::SampleId&) {
                          queue.push([c](robot::RobotInterface& r) { r.execute(c); });
                        });
  dds::Writer<km::CraneCommand_PubSubType> command(
      s.controller_side, dds::topics::crane_command("arm"), dds::QosFamily::Command);
  Samples<km::CraneState_PubSubType> state(s.controller_side, dds::topics::crane_state("arm"));
  km::CraneCommand_ c;
  c.slew(0.4);
  c.lift(0.1);
  c.hoist(0.05);
  for (int i = 0; i < 3000 && command.matched() == 0; ++i) std::this_thread::sleep_for(10ms);
  ASSERT_GT(command.matched(), 0u);
  command.write(c);
  std::optional<km::CraneState_> seen;
  for (int i = 0; i < 200 && !seen; ++i) {
    node.poll_commands();
    queue.drain(crane_robot);
    crane_robot.advance(0.01 * (i + 1));
    node.publish();
    seen = state.wait_for([](const km::CraneState_& m) { return m.slew() == 0.4; }, 10ms);
  }
  ASSERT_TRUE(seen.has_value());
  EXPECT_EQ(seen->hoist(), 0.05);
}

/// The mock with the plug-in's command: what it was nudged by.
class NudgedMock : public robot::MockRobot {
 public:
  using MockRobot::MockRobot;
  bool execute(const robot::RobotCommand& command) override {
    if (const auto* nudge = command.as<Nudge>()) {
      nudges.push_back(nudge->force);
      return true;
    }
    return MockRobot::execute(command);
  }
  std::vector<double> nudges;
};

// A plug-in's own command reaches the node without an edit to it: served on
// rt/<robot>/command/<name> because the robot declares it, arriving as its type; numbers that
// do not fit it, or are not finite, are dropped at the edge. A robot that declares a command no
// type registers is refused naming it.
TEST(RobotNode, APlugInsOwnCommandArrivesOnItsTopicAsItsType) {
  ASSERT_TRUE(nudge_registered());
  Served s;
  robot::Capabilities with = rover();
  with.commands = {"nudge"};
  NudgedMock ball("ball", with);
  BasicCommandQueue<robot::RobotInterface&> queue;
  robot::RobotNode node(s.robot_side, ball, [&](robot::RobotCommand c, const dds::SampleId&) {
    queue.push([c](robot::RobotInterface& r) { r.execute(c); });
  });
  const auto lines = node.topic_lines();
  EXPECT_NE(std::find(lines.begin(), lines.end(),
                      "rt/ball/command/nudge (std_msgs/Float64MultiArray, in)"),
            lines.end());
  dds::Writer<std_msgs::msg::dds_::Float64MultiArray_PubSubType> command(
      s.controller_side, dds::topics::robot_command("ball", "nudge"), dds::QosFamily::Command);
  for (int i = 0; i < 3000 && command.matched() == 0; ++i) std::this_thread::sleep_for(10ms);
  ASSERT_GT(command.matched(), 0u);
  for (const std::vector<double>& data :
       {std::vector<double>{1.0, 2.0}, {std::nan("")}, std::vector<double>{2.5}}) {
    std_msgs::msg::dds_::Float64MultiArray_ m;
    m.data(data);
    command.write(m);
  }
  for (int i = 0; i < 500 && ball.nudges.empty(); ++i) {
    node.poll_commands();
    queue.drain(ball);
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_EQ(ball.nudges, std::vector<double>{2.5});  // the two that do not fit never came

  robot::Capabilities unknown = rover();
  unknown.commands = {"teleport"};
  robot::MockRobot stranger("stranger", unknown);
  try {
    robot::RobotNode refused(s.robot_side, stranger,
                             [](robot::RobotCommand, const dds::SampleId&) {});
    ADD_FAILURE() << "served a command no type registers";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'teleport'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace macsim::test
