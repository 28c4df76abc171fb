// What a ROS 2 Jazzy node expects of macsim, seen on the wire: TF (tf and a latched tf_static,
// REP-105 frames, a robot prefix), and state topics a default reliable subscription receives.
#include <gtest/gtest.h>
#include <signal.h>

#include <map>
#include <set>

#include "macsim/dds/topics.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/rosgraph_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"
#include "macsim/msg/tf2_msgsPubSubTypes.h"
#include "support/child_process.h"
#include "support/latest_sample.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace tf = tf2_msgs::msg::dds_;

class Ros2Conventions : public ::testing::Test {
 protected:
  void start(std::vector<std::string> extra = {},
             const std::string& world = "worlds/small_room.xml") {
    domain_ = unique_test_domain();
    std::vector<std::string> argv{bin("macsim"),           "--world",   source(world), "--domain",
                                  std::to_string(domain_), "--cameras", "off"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    macsim_ = std::make_unique<ChildProcess>(argv);
    ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
    participant_ =
        std::make_unique<dds::Participant>(dds::ParticipantOptions{domain_, "", "ros2_test"});
  }
  void TearDown() override {
    participant_.reset();
    if (!macsim_) return;
    macsim_->signal(SIGTERM);
    EXPECT_EQ(macsim_->wait_for_exit(10s), 0) << macsim_->output();
  }
  /// parent -> child of every transform seen.
  static std::map<std::string, std::string> edges(const std::vector<tf::TFMessage_>& messages) {
    std::map<std::string, std::string> out;
    for (const auto& m : messages) {
      for (const auto& t : m.transforms()) out[t.child_frame_id()] = t.header().frame_id();
    }
    return out;
  }
  int domain_ = 0;
  std::unique_ptr<ChildProcess> macsim_;
  std::unique_ptr<dds::Participant> participant_;
};

TEST_F(Ros2Conventions, TfCarriesTheRobotsTreeAndTfStaticReachesALateListener) {
  start();
  // a rotating laser and a moving crane show on tf
  Samples<tf::TFMessage_PubSubType> moving(*participant_, dds::topics::kTf, 2000,
                                           dds::QosFamily::State);
  // Each moving frame may come in a message of its own, and the reader may match after some
  // went out: wait until every one of them came at least once.
  std::set<std::string> seen;
  ASSERT_TRUE(moving.wait_for(
      [&](const tf::TFMessage_& m) {
        for (const auto& t : m.transforms()) seen.insert(t.child_frame_id());
        for (const char* frame :
             {"base_footprint", "laser360", "crane_turret", "crane_boom", "crane_magnet"}) {
          if (!seen.count(frame)) return false;
        }
        return true;
      },
      20s))
      << "frames seen: " << seen.size();
  const auto dynamic = edges(moving.all());
  EXPECT_EQ(dynamic.at("base_footprint"), "odom");  // REP-105
  EXPECT_EQ(dynamic.at("laser360"), "base_link");
  EXPECT_EQ(dynamic.at("crane_turret"), "base_link");
  EXPECT_EQ(dynamic.at("crane_boom"), "crane_turret");
  EXPECT_EQ(dynamic.at("crane_magnet"), "crane_boom");

  // tf_static, transient local: a listener that comes late still gets every mount
  std::this_thread::sleep_for(1s);
  Samples<tf::TFMessage_PubSubType> fixed(*participant_, dds::topics::kTfStatic, 10,
                                          dds::QosFamily::Latched);
  const auto got =
      fixed.wait_for([](const tf::TFMessage_& m) { return !m.transforms().empty(); }, 10s);
  ASSERT_TRUE(got);
  const auto mounts = edges({*got});
  EXPECT_EQ(mounts.at("base_link"), "base_footprint");
  for (const char* sensor :
       {"ultrasound_front", "ir_left_front", "ir_left", "ir_left_back", "ir_back", "ir_right_back",
        "ir_right", "ir_right_front", "left_camera", "right_camera"}) {
    EXPECT_EQ(mounts.at(sensor), "base_link") << sensor;
  }
  EXPECT_EQ(mounts.at("left_camera_optical_frame"), "left_camera");
  EXPECT_EQ(mounts.at("right_camera_optical_frame"), "right_camera");
  for (const auto& t : got->transforms()) {
    if (t.child_frame_id() != "base_link") continue;
    EXPECT_NEAR(t.transform().translation().z(), 0.107 + 0.379 / (2 * M_PI), 1e-3);
  }
  // the odometry says the same frames
  Samples<nav_msgs::msg::dds_::Odometry_PubSubType> odom(*participant_, dds::topics::odom("kurt"));
  const auto o = odom.wait_for([](const auto&) { return true; }, 10s);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->header().frame_id(), "odom");
  EXPECT_EQ(o->child_frame_id(), "base_footprint");
}

TEST_F(Ros2Conventions, RobotFramesPutTheRobotsNameBeforeEveryFrame) {
  start({"--robot-frames"});
  Samples<tf::TFMessage_PubSubType> fixed(*participant_, dds::topics::kTfStatic, 10,
                                          dds::QosFamily::Latched);
  const auto got =
      fixed.wait_for([](const tf::TFMessage_& m) { return !m.transforms().empty(); }, 20s);
  ASSERT_TRUE(got);
  EXPECT_EQ(edges({*got}).at("kurt/base_link"), "kurt/base_footprint");
  Samples<nav_msgs::msg::dds_::Odometry_PubSubType> odom(*participant_, dds::topics::odom("kurt"));
  Samples<sensor_msgs::msg::dds_::Range_PubSubType> ranges(*participant_,
                                                           dds::topics::range("kurt"));
  const auto o = odom.wait_for([](const auto&) { return true; }, 10s);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->header().frame_id(), "kurt/odom");
  EXPECT_EQ(o->child_frame_id(), "kurt/base_footprint");
  const auto r = ranges.wait_for([](const auto&) { return true; }, 10s);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->header().frame_id().rfind("kurt/", 0), 0u) << r->header().frame_id();
}

TEST_F(Ros2Conventions, CmdVelStampedDrivesTheRobot) {
  start({"--cmd-vel-stamped"});
  EXPECT_NE(macsim_->output().find("rt/kurt/cmd_vel (geometry_msgs/TwistStamped, in)"),
            std::string::npos)
      << macsim_->output();
  ChildProcess pub({bin("macsim_topic"), "pub", "/kurt/cmd_vel", "geometry_msgs/msg/TwistStamped",
                    "{header: {frame_id: base_link}, twist: {linear: {x: 0.3}}}", "--rate", "10",
                    "--times", "15", "--domain", std::to_string(domain_)});
  ASSERT_EQ(pub.wait_for_exit(30s), 0) << pub.output();
  Samples<nav_msgs::msg::dds_::Odometry_PubSubType> odom(*participant_, dds::topics::odom("kurt"));
  const auto moved =
      odom.wait_for([](const auto& o) { return o.pose().pose().position().x() > 0.2; }, 10s);
  EXPECT_TRUE(moved) << "the robot did not drive on TwistStamped commands";
}

TEST_F(Ros2Conventions, TheWorldStateComesUnkeyedAndStampedForRosNodes) {
  start(std::vector<std::string>{}, "worlds/DemoWorld_v1.xml");
  // a plain (unkeyed, reliable, volatile) reader, as rmw_fastrtps makes
  Samples<macsim_msgs::msg::dds_::ObjectList_PubSubType> objects(
      *participant_, dds::topics::kWorldObjectList, 10, dds::QosFamily::State);
  Samples<macsim_msgs::msg::dds_::DoorList_PubSubType> doors(
      *participant_, dds::topics::kWorldDoorList, 10, dds::QosFamily::State);
  const auto list = objects.wait_for([](const auto&) { return true; }, 10s);
  ASSERT_TRUE(list);
  EXPECT_EQ(list->objects().size(), 24u);  // DemoWorld_v1's objects
  EXPECT_EQ(list->header().frame_id(), "world");
  EXPECT_GT(list->header().stamp().sec() * 1000000000LL + list->header().stamp().nanosec(), 0);
  std::set<std::string> names;
  for (const auto& o : list->objects()) names.insert(o.name());
  EXPECT_EQ(names.count("environment_00/can_heavy_01"), 1u);
  const auto door_list = doors.wait_for([](const auto&) { return true; }, 10s);
  ASSERT_TRUE(door_list);
  EXPECT_EQ(door_list->doors().size(), 1u);
}

TEST_F(Ros2Conventions, DefaultReliableReadersGetOdometryImuJointStatesAndClock) {
  start();
  // A plain rclcpp subscription: reliable, volatile, keep last 10 (the state family's reader).
  Samples<nav_msgs::msg::dds_::Odometry_PubSubType> odom(*participant_, dds::topics::odom("kurt"),
                                                         1000, dds::QosFamily::State);
  Samples<sensor_msgs::msg::dds_::Imu_PubSubType> imu(*participant_, dds::topics::imu("kurt"), 1000,
                                                      dds::QosFamily::State);
  Samples<sensor_msgs::msg::dds_::JointState_PubSubType> joints(
      *participant_, dds::topics::joint_states("kurt"), 1000, dds::QosFamily::State);
  Samples<rosgraph_msgs::msg::dds_::Clock_PubSubType> clock(*participant_, dds::topics::kClock,
                                                            1000, dds::QosFamily::State);
  // As many as come in about 3 s at real time; a loaded machine takes longer to step them.
  EXPECT_TRUE(odom.wait_for_count(51, 60s)) << odom.all().size();
  EXPECT_TRUE(imu.wait_for_count(51, 30s)) << imu.all().size();
  EXPECT_TRUE(joints.wait_for_count(51, 30s)) << joints.all().size();
  ASSERT_TRUE(clock.wait_for_count(51, 30s)) << clock.all().size();
  const auto ticks = clock.all();
  // reliable: no 10 ms tick of the clock missing between the first and the last seen
  for (std::size_t i = 1; i < ticks.size(); ++i) {
    const auto ns = [](const auto& c) {
      return c.clock().sec() * 1000000000LL + c.clock().nanosec();
    };
    EXPECT_EQ(ns(ticks[i]) - ns(ticks[i - 1]), 10000000LL) << i;
  }
}

}  // namespace
}  // namespace macsim::test
