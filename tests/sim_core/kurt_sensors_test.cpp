// The KURT3D's senses against known geometry: IR/sonar, the laser on its rotating unit, the
// assembled cloud, the gyro and tilt, and the real driver's conversions.
#include <gtest/gtest.h>

#include "macsim/sim_core/kurt_robot.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

const double kBaseLinkHeight = 0.107 + 0.379 / (2 * M_PI);  // 0.1673 m above the floor

World world_with(const std::string& type, const std::string& extra = "") {
  return World(load_world_string("<WORLD><ROBOT><ID>kurt</ID><TYPE>" + type +
                                     "</TYPE></ROBOT>" + extra + "</WORLD>",
                                 "sensors.xml"));
}

// A fixed wall: its face towards the robot at distance `face` along +x (or +y with `side`).
std::string wall(double face, bool side = false) {
  const double centre = face + 0.05;
  const std::string pos = side ? "0," + std::to_string(centre) : std::to_string(centre) + ",0";
  const std::string dims = side ? "6,0.1,1" : "0.1,6,1";
  return "<OBJECT><ID>wall" + std::string(side ? "_side" : "") + "</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE><DIMS>" +
         dims + "</DIMS><POS>" + pos + ",0.5</POS></OBJECT>";
}

const RangeReading& reading(const KurtRobot& kurt, const std::string& frame) {
  for (const auto& r : kurt.state().ranges) {
    if (frame == r.sensor->frame) return r;
  }
  throw std::runtime_error("no sensor " + frame);
}

TEST(KurtDriverConversions, IrAndSonarAsTheDriverComputesThem) {
  // Invalid outside the raw windows, as kurt.cc checks them.
  EXPECT_EQ(ir_range_from_raw(99), kInvalidRange);
  EXPECT_EQ(ir_range_from_raw(801), kInvalidRange);
  EXPECT_EQ(sonar_range_from_raw(1001), kInvalidRange);
  // raw 300: (30000/290)^(1/1.4) - 10 = 17.47 cm -> 17 cm.
  EXPECT_DOUBLE_EQ(ir_range_from_raw(300), 0.17);
  // raw 500: 0.110652 * 500 + 11.9231 = 67.25 cm -> 67 cm.
  EXPECT_DOUBLE_EQ(sonar_range_from_raw(500), 0.67);
  // The driver compares raw ADC counts with limits meant in mm: IR readings are valid only
  // up to 0.53 m, ultrasound only from 0.23 m.
  for (double d : {0.12, 0.3, 0.5}) EXPECT_NEAR(ir_range_from_raw(ir_raw_from_range(d)), d, 0.011) << d;
  for (double d : {0.3, 0.5, 0.95}) EXPECT_NEAR(sonar_range_from_raw(sonar_raw_from_range(d)), d, 0.011) << d;
  EXPECT_EQ(ir_range_from_raw(ir_raw_from_range(0.6)), kInvalidRange);
  EXPECT_EQ(sonar_range_from_raw(sonar_raw_from_range(0.2)), kInvalidRange);
  // Rotunit: pi/6 rad/s is sent as 42, which means 0.5154 rad/s.
  EXPECT_EQ(rotunit_speed_command(M_PI / 6), 42);
  EXPECT_NEAR(rotunit_speed_from_command(42), 42 * 2 * M_PI * 20 / 10240, 1e-15);
  EXPECT_NEAR(rotunit_angle_from_ticks(2560), M_PI / 2, 1e-15);
}

TEST(KurtRanges, SonarAndIrMeasureTheDistanceToAWall) {
  World world = world_with("kurt3d", wall(0.717) + wall(0.565, true));
  run_for(world, 0.2);
  const KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  // ultrasound_front sits at x = 0.217: the wall face is 0.5 m ahead of it.
  EXPECT_NEAR(reading(kurt, "ultrasound_front").range, 0.5, 0.011);  // whole centimetres
  // ir_left sits at y = 0.165: the side wall is 0.4 m away.
  EXPECT_NEAR(reading(kurt, "ir_left").range, 0.4, 0.011);
  // Nothing within reach behind or to the right: invalid, as the driver reports it.
  EXPECT_EQ(reading(kurt, "ir_back").range, kInvalidRange);
  EXPECT_EQ(reading(kurt, "ir_right").range, kInvalidRange);
}

TEST(KurtRanges, TooCloseIsInvalidToo) {
  World world = world_with("kurt3d", wall(0.217 + 0.05));
  run_for(world, 0.2);
  EXPECT_EQ(reading(*world.robot_as<KurtRobot>("kurt"), "ultrasound_front").range, kInvalidRange);
}

TEST(KurtLaser, AFixedLms200ScansTheHorizontalPlane) {
  World world = world_with("kurt2", wall(2.145) + wall(1.5, true));
  run_for(world, 0.5);
  const LaserScan& scan = world.robot_as<KurtRobot>("kurt")->state().scan;
  ASSERT_EQ(scan.ranges.size(), 181u);
  EXPECT_NEAR(scan.angle_min, -M_PI / 2, 1e-15);
  EXPECT_NEAR(scan.angle_increment, M_PI / 180, 1e-15);
  // The scanner is at x = 0.145 from base_link: the front wall is 2 m from it.
  for (int i = 60; i <= 120; ++i) {
    const double a = scan.angle_min + i * scan.angle_increment;
    const double expected = 2.0 / std::cos(a);
    if (std::fabs(expected * std::sin(a)) > 1.4) continue;  // that beam meets the side wall
    EXPECT_NEAR(scan.ranges[i], expected, 0.025) << "beam " << i;  // 5 sigma of 5 mm noise
  }
  EXPECT_NEAR(scan.ranges[180], 1.5, 0.025);  // +90 degrees: the side wall
  EXPECT_TRUE(std::isinf(scan.ranges[0]));    // -90 degrees: nothing within 10 m
  EXPECT_EQ(world.robot_as<KurtRobot>("kurt")->state().scans, 37u);  // 75 Hz for 0.5 s
}

TEST(KurtLaser, TheRotatingScannerSeesTheFloorAndAssemblesA3dCloud) {
  World world = world_with("kurt3d", wall(2.0));
  KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  kurt.command_rotunit(M_PI / 6);
  const double speed = rotunit_speed_from_command(42);
  run_for(world, 2 * M_PI / speed + 0.2);
  const LaserScan& scan = kurt.state().scan;
  const double height = kBaseLinkHeight + scan.origin.z();
  // Beam 0 looks straight down, beam 45 down at 45 degrees: both hit the floor.
  EXPECT_NEAR(scan.ranges[0], height, 0.025);
  EXPECT_NEAR(scan.ranges[45], height / std::sin(M_PI / 4), 0.025);
  ASSERT_EQ(kurt.state().clouds, 1u);
  const PointCloud& cloud = kurt.state().cloud;
  EXPECT_GT(cloud.points.size(), 10000u);
  // Points on the floor lie at z = -0.1673 in base_link; the wall at x = 2 faces the robot.
  int floor = 0, on_wall = 0;
  for (const auto& p : cloud.points) {
    if (std::fabs(p.z() + kBaseLinkHeight) < 0.02) ++floor;
    if (std::fabs(p.x() - 2.0) < 0.02 && p.z() > -0.1) ++on_wall;
  }
  EXPECT_GT(floor, 3000);
  EXPECT_GT(on_wall, 100);
  // The rotunit reports its angle in 10240 ticks per turn.
  const double ticks = kurt.rotunit_angle() / (2 * M_PI) * 10240;
  EXPECT_NEAR(ticks, std::round(ticks), 1e-6);
}

TEST(KurtImu, GyroYawFollowsTheTurnAndDriftsWhenAsked) {
  World world = world_with("kurt3d");
  KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  for (int i = 0; i < 2000; ++i) {
    if (i % 100 == 0) kurt.command_twist(0.0, 0.6, world.time());
    world.step();
  }
  const Eigen::Vector3d x = kurt.base_link_pose().orientation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(kurt.state().imu.yaw, std::atan2(x.y(), x.x()), 1e-9);  // no noise by default
  EXPECT_GT(kurt.state().imu.yaw, 0.5);
  EXPECT_NEAR(kurt.state().imu.roll, 0.0, 0.01);

  KurtConfig drifting = *find_kurt_type("kurt3d");
  drifting.gyro_drift = 0.01;
  register_kurt_type("kurt3d_drifting_gyro", drifting);
  World still = world_with("kurt3d_drifting_gyro");
  run_for(still, 10.0);
  EXPECT_NEAR(still.robot_as<KurtRobot>("kurt")->state().imu.yaw, 0.1, 0.005);  // 0.01 rad/s for 10 s
}

TEST(KurtImu, GyroYawIsRelativeToTheStartHeading) {
  // A robot placed with a heading reads yaw 0 at the start and the turn since then after it.
  World world(load_world_string(
      "<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE><ROT>0,0,120</ROT></ROBOT></WORLD>",
      "turned.xml"));
  KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  run_for(world, 0.05);
  EXPECT_NEAR(kurt.state().imu.yaw, 0.0, 1e-3);
  for (int i = 0; i < 1500; ++i) {
    if (i % 100 == 0) kurt.command_twist(0.0, 0.6, world.time());
    world.step();
  }
  const Eigen::Vector3d x = kurt.base_link_pose().orientation * Eigen::Vector3d::UnitX();
  const double turned = std::atan2(x.y(), x.x()) - 120.0 * M_PI / 180.0;
  EXPECT_GT(kurt.state().imu.yaw, 0.3);
  EXPECT_NEAR(kurt.state().imu.yaw, std::atan2(std::sin(turned), std::cos(turned)), 1e-6);
}

}  // namespace
}  // namespace macsim::test
