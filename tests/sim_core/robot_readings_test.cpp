// What every robot model shares in making its readings: mounts as the node publishes them, the
// stereo pair's optical frames (z ahead, x right, y down), odometry with wrapped wheel angles,
// ground truth in the robot's frame, a sweep as served.
#include "robot_readings.h"

#include <gtest/gtest.h>
#include <ode/ode.h>

#include <cmath>

#include "macsim/sim_core/diff_drive_robot.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"

namespace macsim::detail {
namespace {

Eigen::Quaterniond quaternion(const std::array<double, 4>& xyzw) {
  return Eigen::Quaterniond(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
}

TEST(RobotReadings, AMountKeepsItsFramesPositionAndRotation) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const robot::Mount m = robot_mount("base_link", "laser", {0.1, -0.2, 0.3}, q);
  EXPECT_EQ(m.parent, "base_link");
  EXPECT_EQ(m.child, "laser");
  EXPECT_EQ(m.position, (std::array<double, 3>{0.1, -0.2, 0.3}));
  EXPECT_TRUE(quaternion(m.orientation).isApprox(q));
}

TEST(RobotReadings, TheOpticalFrameLooksAlongTheCamerasX) {
  StereoMount cameras;
  cameras.left.position = {0.05, 0.06, 0.42};
  cameras.right.position = {0.05, -0.06, 0.42};
  robot::Frames frames;
  add_stereo_frames(cameras, frames);
  ASSERT_EQ(frames.mounts.size(), 4u);
  EXPECT_EQ(frames.mounts[0].child, "left_camera");
  EXPECT_EQ(frames.mounts[1].parent, "left_camera");
  EXPECT_EQ(frames.mounts[1].child, "left_camera_optical_frame");
  EXPECT_EQ(frames.mounts[3].child, "right_camera_optical_frame");
  const Eigen::Quaterniond optical = quaternion(frames.mounts[1].orientation);
  EXPECT_TRUE((optical * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));
  EXPECT_TRUE((optical * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY()));
  EXPECT_TRUE((optical * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_DOUBLE_EQ(frames.mounts[2].position[1], -0.06);
}

TEST(RobotReadings, OdometryWrapsTheWheelAngles) {
  PlanarOdometry o;
  o.x = 1.5;
  o.yaw = -0.25;
  o.linear = 0.3;
  const robot::Odometry r = odometry_reading(o, 3 * M_PI + 0.1, -2 * M_PI - 0.2);
  EXPECT_EQ(r.x, 1.5);
  EXPECT_EQ(r.yaw, -0.25);
  EXPECT_EQ(r.linear, 0.3);
  EXPECT_NEAR(r.left_wheel, -M_PI + 0.1, 1e-12);
  EXPECT_NEAR(r.right_wheel, -0.2, 1e-12);
}

TEST(RobotReadings, GroundTruthVelocitiesAreInTheRobotsFrame) {
  // A diff-drive robot turned 90 degrees, pushed along the world's y: ahead in its own frame.
  World world(load_world_string(R"(<WORLD><PHYSICS><GRAVITY>0,0,0</GRAVITY></PHYSICS>
      <ROBOT><ID>r</ID><TYPE>diff_drive</TYPE><POS>1,2,0</POS><ROT>0,0,90</ROT></ROBOT></WORLD>)",
                                  "turned.xml"));
  RobotModel* robot = world.robot("r");
  ASSERT_NE(robot, nullptr);
  for (dxBody* body : robot->bodies()) dBodySetLinearVel(body, 0, 0.5, 0);
  const robot::GroundTruth g = ground_truth_reading(*robot);
  EXPECT_NEAR(g.position[0], 1.0, 1e-6);
  EXPECT_NEAR(g.position[1], 2.0, 1e-6);
  EXPECT_NEAR(g.linear[0], 0.5, 1e-9);
  EXPECT_NEAR(g.linear[1], 0.0, 1e-9);
  EXPECT_NEAR(std::abs(g.orientation[2]), std::sin(M_PI / 4), 1e-6);
}

TEST(RobotReadings, ASweepIsServedWithItsFrameAndPeriod) {
  LaserScan s;
  s.angle_min = -1.0;
  s.angle_increment = 0.01;
  s.range_min = 0.05;
  s.range_max = 8.0;
  s.ranges = {1.0f, INFINITY, 2.5f};
  const robot::Scan r = scan_reading(s, "laser", 0.1);
  EXPECT_EQ(r.frame, "laser");
  EXPECT_EQ(r.angle_min, -1.0);
  EXPECT_EQ(r.angle_increment, 0.01);
  EXPECT_EQ(r.range_max, 8.0);
  EXPECT_EQ(r.scan_time, 0.1);
  EXPECT_EQ(r.ranges, s.ranges);
}

}  // namespace
}  // namespace macsim::detail
