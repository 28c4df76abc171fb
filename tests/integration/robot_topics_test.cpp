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
  std::this_thread::sleep_for(500ms);

  std::set<std::string> frames;
  for (const auto& r : ranges.all()) frames.insert(r.header().frame_id());
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

}  // namespace
}  // namespace macsim::test
