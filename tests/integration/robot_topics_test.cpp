// Every robot topic of macsim, seen from another process over real DDS: ranges, IMU, laser,
// clouds, joint states, crane, cameras; commands for the rotating unit, crane and magnet.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <set>

#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"
#include "macsim/msg/std_msgsPubSubTypes.h"
#include "support/child_process.h"
#include "support/latest_sample.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace sm = sensor_msgs::msg::dds_;
namespace km = kurt_msgs::msg::dds_;

class RobotTopics : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = unique_test_domain();
    // Four times real time: a full rotunit turn (12 s of sim time) takes 3 s.
    macsim_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{bin("macsim"), "--world", source("worlds/small_room.xml"),
                                 "--domain", std::to_string(domain_), "--rtf", "4"});
    ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
    participant_ =
        std::make_unique<dds::Participant>(dds::ParticipantOptions{domain_, "", "topics_test"});
  }
  void TearDown() override {
    participant_.reset();
    macsim_->signal(SIGTERM);
    EXPECT_EQ(macsim_->wait_for_exit(10s), 0) << macsim_->output();
  }

  int domain_ = 0;
  std::unique_ptr<ChildProcess> macsim_;
  std::unique_ptr<dds::Participant> participant_;
};

TEST_F(RobotTopics, RangesImuJointStatesAndTheLaserArrive) {
  Samples<sm::Range_PubSubType> ranges(*participant_, dds::topics::range("kurt"));
  Samples<sm::Imu_PubSubType> imu(*participant_, dds::topics::imu("kurt"));
  Samples<sm::LaserScan_PubSubType> scans(*participant_, dds::topics::scan("kurt", true));
  Samples<sm::JointState_PubSubType> joints(*participant_, dds::topics::joint_states("kurt"));
  ASSERT_TRUE(scans.wait_for([](const auto&) { return true; }, 20s));
  // Every range sensor heard from (and the IMU), however long a loaded machine takes to step.
  std::set<std::string> frames;
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (std::chrono::steady_clock::now() < deadline && (frames.size() < 8 || !imu.latest())) {
    for (const auto& r : ranges.all()) frames.insert(r.header().frame_id());
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(frames.size(), 8u);  // all eight sensors, told apart by frame_id
  EXPECT_TRUE(frames.count("ultrasound_front"));
  for (const auto& r : ranges.all()) {
    EXPECT_TRUE(r.range() == -0.01f || (r.range() >= r.min_range() && r.range() <= r.max_range()));
  }
  ASSERT_TRUE(imu.latest());
  EXPECT_EQ(imu.latest()->header().frame_id(), "base_link");
  EXPECT_EQ(imu.latest()->angular_velocity_covariance()[0], -1.0);

  const auto scan = *scans.latest();
  EXPECT_EQ(scan.header().frame_id(), "laser360");
  ASSERT_EQ(scan.ranges().size(), 181u);
  // Beam 0 looks straight down from 0.35 m above base_link: the floor is 0.517 m away.
  EXPECT_NEAR(scan.ranges()[0], 0.107 + 0.379 / (2 * M_PI) + 0.35, 0.03);

  auto wheels = joints.wait_for([](const auto& j) { return j.name().size() == 6; }, 5s);
  ASSERT_TRUE(wheels);
  EXPECT_EQ(wheels->name()[1], "left_middle_wheel_joint");
}

TEST_F(RobotTopics, TheRotatingUnitTurnsOnRotVelAndCloudsAreAssembled) {
  Samples<sm::JointState_PubSubType> joints(*participant_, dds::topics::joint_states("kurt"));
  Samples<sm::PointCloud2_PubSubType> clouds(*participant_, dds::topics::points("kurt"), 2);
  dds::Writer<geometry_msgs::msg::dds_::Twist_PubSubType> rot_vel(
      *participant_, dds::topics::rot_vel("kurt"), dds::QosFamily::Command);
  // Commands go out again until they show: a volatile reader matching late misses earlier ones.
  std::optional<sm::JointState_> turning;
  for (int i = 0; i < 100 && !turning; ++i) {
    rot_vel.write(dds::planar_twist(0.0, M_PI / 6));
    turning = joints.wait_for(
        [](const auto& j) { return j.name().size() == 1 && j.position()[0] > 0.5; }, 200ms);
  }
  ASSERT_TRUE(turning) << "laser_rot_joint never turned";
  EXPECT_EQ(turning->name()[0], "laser_rot_joint");
  ASSERT_EQ(turning->velocity().size(), 1u);  // the speed as the rotunit's units quantize it
  EXPECT_DOUBLE_EQ(turning->velocity()[0], 42 * 2 * M_PI * 20 / 10240);
  auto cloud = clouds.wait_for([](const auto&) { return true; }, 30s);
  ASSERT_TRUE(cloud) << "no assembled cloud";
  EXPECT_EQ(cloud->fields().size(), 3u);
  EXPECT_EQ(cloud->point_step(), 12u);
  EXPECT_GT(cloud->width(), 10000u);
  EXPECT_EQ(cloud->data().size(), cloud->width() * 12u);
}

TEST_F(RobotTopics, TheCraneAndItsMagnetObeyAndReport) {
  Samples<km::CraneState_PubSubType> crane(*participant_, dds::topics::crane_state("kurt"));
  dds::Writer<km::CraneCommand_PubSubType> command(
      *participant_, dds::topics::crane_command("kurt"), dds::QosFamily::Command);
  dds::Writer<km::MagnetCommand_PubSubType> magnet(*participant_, dds::topics::crane_magnet("kurt"),
                                                   dds::QosFamily::Command);
  km::CraneCommand_ target;
  target.slew(0.5);
  target.hoist(0.1);
  km::MagnetCommand_ on;
  on.on(true);
  // Commands go out again until they show: a volatile reader matching late misses earlier ones.
  std::optional<km::CraneState_> there;
  for (int i = 0; i < 100 && !there; ++i) {
    command.write(target);
    magnet.write(on);
    there = crane.wait_for(
        [](const auto& s) {
          return std::fabs(s.slew() - 0.5) < 0.02 && std::fabs(s.hoist() - 0.1) < 0.01 &&
                 s.magnet_on();
        },
        200ms);
  }
  ASSERT_TRUE(there) << (crane.latest() ? std::to_string(crane.latest()->slew()) : "no state");
  EXPECT_TRUE(there->held_object().empty());  // nothing magnetizable below it
}

TEST_F(RobotTopics, WheelSpeedCommandsTurnTheRobot) {
  Samples<nav_msgs::msg::dds_::Odometry_PubSubType> odom(*participant_, dds::topics::odom("kurt"),
                                                         5);
  dds::Writer<km::WheelSpeeds_PubSubType> wheels(*participant_, dds::topics::wheel_speeds("kurt"),
                                                 dds::QosFamily::Command);
  km::WheelSpeeds_ spin;
  spin.left(-0.1);
  spin.right(0.1);
  std::optional<nav_msgs::msg::dds_::Odometry_> turned;
  for (int i = 0; i < 100 && !turned; ++i) {  // repeated, as a controller does (0.6 s timeout)
    wheels.write(spin);
    turned =
        odom.wait_for([](const auto& o) { return o.twist().twist().angular().z() > 0.2; }, 100ms);
  }
  ASSERT_TRUE(turned) << "the robot did not turn counter-clockwise";
  EXPECT_NEAR(turned->twist().twist().linear().x(), 0.0, 0.02);
}

TEST_F(RobotTopics, StereoImagesAndCalibrationArrive) {
  Samples<sm::Image_PubSubType> left(*participant_, dds::topics::image("kurt", "left"), 3);
  Samples<sm::Image_PubSubType> right(*participant_, dds::topics::image("kurt", "right"), 3);
  Samples<sm::CameraInfo_PubSubType> right_info(*participant_,
                                                dds::topics::camera_info("kurt", "right"), 3);
  auto l = left.wait_for([](const auto&) { return true; }, 20s);
  auto r = right.wait_for([](const auto&) { return true; }, 20s);
  auto info = right_info.wait_for([](const auto&) { return true; }, 20s);
  ASSERT_TRUE(l && r && info);
  EXPECT_EQ(l->width(), 320u);
  EXPECT_EQ(l->height(), 240u);
  EXPECT_EQ(l->encoding(), "bgr8");
  EXPECT_EQ(l->data().size(), 320u * 240u * 3u);
  EXPECT_NE(l->data(), r->data());  // two viewpoints
  std::set<uint8_t> values(l->data().begin(), l->data().end());
  EXPECT_GT(values.size(), 20u);  // a picture, not a blank
  // Right camera: P[3] = -f * baseline (0.12 m).
  EXPECT_NEAR(info->p()[3], -info->k()[0] * 0.12, 1e-9);
}

// A second robot type beside the KURT3D (worlds/two_robots.xml): the diff-drive "rover" is
// served by the same node on rt/rover/*: its description, its planar laser, its odometry, and
// cmd_vel drives it towards the wall 3 m ahead.
TEST(TwoRobotTypes, TheDiffDriveRoverIsServedBesideTheKurt) {
  const int domain = unique_test_domain();
  ChildProcess macsim({bin("macsim"), "--world", source("worlds/two_robots.xml"), "--domain",
                       std::to_string(domain), "--rtf", "2"});
  ASSERT_TRUE(macsim.wait_for_output("stepping", 30s)) << macsim.output();
  {
    dds::Participant participant(dds::ParticipantOptions{domain, "", "rover_test"});
    Samples<std_msgs::msg::dds_::String_PubSubType> description(
        participant, dds::topics::robot_description("rover"), 10, dds::QosFamily::Latched);
    Samples<std_msgs::msg::dds_::String_PubSubType> kurt_description(
        participant, dds::topics::robot_description("kurt"), 10, dds::QosFamily::Latched);
    Samples<sm::LaserScan_PubSubType> scans(participant, dds::topics::scan("rover", false), 5);
    Samples<nav_msgs::msg::dds_::Odometry_PubSubType> odom(participant,
                                                           dds::topics::odom("rover"), 5);
    Samples<nav_msgs::msg::dds_::Odometry_PubSubType> kurt_odom(participant,
                                                                dds::topics::odom("kurt"), 5);
    dds::Writer<geometry_msgs::msg::dds_::Twist_PubSubType> cmd_vel(
        participant, dds::topics::cmd_vel("rover"), dds::QosFamily::Command);

    auto text = description.wait_for([](const auto&) { return true; }, 20s);
    ASSERT_TRUE(text) << "no rt/rover/robot_description";
    EXPECT_EQ(text->data().rfind("robot diff_drive\n", 0), 0u) << text->data();
    auto kurt_text = kurt_description.wait_for([](const auto&) { return true; }, 20s);
    ASSERT_TRUE(kurt_text);
    EXPECT_EQ(kurt_text->data().rfind("robot kurt3d\n", 0), 0u);

    // The wall's face is 3.0 m ahead of the rover's centre; the laser sits 0.10 m ahead of it.
    auto first = scans.wait_for([](const auto&) { return true; }, 20s);
    ASSERT_TRUE(first) << "no scan on rt/rover/scan";
    EXPECT_EQ(first->header().frame_id(), "laser");
    ASSERT_EQ(first->ranges().size(), 241u);
    const std::size_t ahead = first->ranges().size() / 2;
    EXPECT_NEAR(first->ranges()[ahead], 2.9, 0.03);

    // Driven at 0.5 m/s (cmd_vel repeated, as a controller does) until 1 m was covered.
    std::optional<nav_msgs::msg::dds_::Odometry_> moved;
    for (int i = 0; i < 200 && !moved; ++i) {
      cmd_vel.write(dds::planar_twist(0.5, 0.0));
      moved = odom.wait_for([](const auto& o) { return o.pose().pose().position().x() > 1.0; },
                            50ms);
    }
    ASSERT_TRUE(moved) << "the rover did not drive 1 m";
    EXPECT_NEAR(moved->pose().pose().position().y(), 0.0, 0.05);
    auto nearer = scans.wait_for(
        [](const auto& s) { return s.ranges()[s.ranges().size() / 2] < 1.95; }, 5s);
    ASSERT_TRUE(nearer) << "the laser did not see the wall come nearer";
    // The KURT beside it was not commanded: it stays where it is.
    auto still = kurt_odom.wait_for([](const auto&) { return true; }, 5s);
    ASSERT_TRUE(still);
    EXPECT_NEAR(still->pose().pose().position().x(), 0.0, 0.01);
  }
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0) << macsim.output();
}

}  // namespace
}  // namespace macsim::test
