// The second robot type, built through RobotModel alone: it stands, drives and turns on its two
// wheels, its odometry follows the ground truth, its laser sees a wall where it is, its state
// is saved and restored with the world's, and it stops when commands stop.
#include "macsim/sim_core/diff_drive_robot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world.h"
#include "support/world_helpers.h"

namespace macsim {
namespace {

using test::run_for;
using test::drive;
using test::yaw_of;

WorldSpec rover_world(const std::string& wall = "") {
  return load_world_string(R"(<WORLD><ROBOT><ID>rover</ID><TYPE>diff_drive</TYPE>
      <POS>0,0,0</POS></ROBOT>)" + wall + "</WORLD>",
                           "rover.xml");
}

const std::string kWall = R"(<OBJECT><ID>wall</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE>
    <DIMS>0.1,3,0.5</DIMS><POS>2.05,0,0.25</POS></OBJECT>)";

TEST(DiffDriveRobot, StandsOnItsWheelsWithBaseLinkAtTheAxles) {
  World world(rover_world());
  run_for(world, 1.0);
  auto* rover = world.robot_as<DiffDriveRobot>("rover");
  ASSERT_NE(rover, nullptr);
  EXPECT_EQ(world.robot_as<KurtRobot>("rover"), nullptr);  // a type of its own
  EXPECT_NEAR(rover->base_footprint_pose().position.z(), 0.0, 0.005);
  EXPECT_NEAR(rover->base_link_pose().position.z(), rover->config().wheel_radius, 0.005);
  EXPECT_LT(rover->base_footprint_pose().position.head<2>().norm(), 0.005);
}

TEST(DiffDriveRobot, DrivesStraightAndItsOdometryFollows) {
  World world(rover_world());
  run_for(world, 0.5);
  drive(world, "rover", 0.4, 0.0, 3.0);
  const RobotModel& rover = *world.robot("rover");
  const Pose truth = rover.base_footprint_pose();
  EXPECT_NEAR(truth.position.x(), 1.2, 0.15);
  EXPECT_NEAR(truth.position.y(), 0.0, 0.05);
  const PlanarOdometry odometry = rover.odometry();
  EXPECT_NEAR(odometry.x, truth.position.x(), 0.03);
  EXPECT_NEAR(odometry.y, truth.position.y(), 0.03);
  EXPECT_NEAR(odometry.linear, 0.4, 0.05);
}

TEST(DiffDriveRobot, TurnsOnTheSpot) {
  World world(rover_world());
  run_for(world, 0.5);
  drive(world, "rover", 0.0, 0.8, 1.5);  // 1.2 rad
  const RobotModel& rover = *world.robot("rover");
  EXPECT_NEAR(yaw_of(rover.base_footprint_pose()), 1.2, 0.15);
  EXPECT_NEAR(rover.odometry().yaw, yaw_of(rover.base_footprint_pose()), 0.05);
  EXPECT_LT(rover.base_footprint_pose().position.head<2>().norm(), 0.05);
}

TEST(DiffDriveRobot, StopsWhenCommandsStop) {
  World world(rover_world());
  drive(world, "rover", 0.4, 0.0, 1.0);
  run_for(world, 1.5);  // the command timed out after 0.5 s
  const RobotModel& rover = *world.robot("rover");
  EXPECT_LT(rover.linear_velocity().norm(), 0.01);
  const double x = rover.base_footprint_pose().position.x();
  run_for(world, 1.0);
  EXPECT_NEAR(rover.base_footprint_pose().position.x(), x, 0.002);
}

TEST(DiffDriveRobot, ItsLaserSeesTheWallAhead) {
  World world(rover_world(kWall));
  run_for(world, 0.25);
  const RobotModel& rover = *world.robot("rover");
  ReadMark mark;
  const robot::Readings readings = rover.read(mark, world.time());
  ASSERT_TRUE(readings.scan);
  const robot::Scan& scan = *readings.scan;
  EXPECT_EQ(scan.frame, "laser");
  const auto& config = world.robot_as<DiffDriveRobot>("rover")->config();
  ASSERT_EQ(scan.ranges.size(), static_cast<std::size_t>(config.laser_beams));
  // The middle beam looks straight ahead: the wall's face at x = 2.0, the laser at x = 0.10.
  EXPECT_NEAR(scan.ranges[scan.ranges.size() / 2], 2.0 - config.laser_position.x(), 0.01);
  // The outermost beams look 120 degrees to the sides and back: nothing within 8 m there.
  EXPECT_TRUE(std::isinf(scan.ranges.front()));
  EXPECT_NEAR(scan.angle_min, -config.laser_fov / 2, 1e-12);
  // Read again at once: nothing new.
  const robot::Readings again = rover.read(mark, world.time());
  EXPECT_FALSE(again.scan);
  EXPECT_FALSE(again.odometry);
}

TEST(DiffDriveRobot, ServesWhatItHasAndDescribesItself) {
  World world(rover_world());
  const RobotModel& rover = *world.robot("rover");
  const robot::Capabilities has = rover.capabilities();
  EXPECT_TRUE(has.laser);
  EXPECT_FALSE(has.laser_rotating || has.crane || has.magnet || has.ranges || has.imu);
  const robot::Frames frames = rover.frames();
  ASSERT_EQ(frames.mounts.size(), 2u);
  EXPECT_EQ(frames.mounts[1].child, "laser");
  EXPECT_TRUE(frames.crane_pivot.child.empty());
  EXPECT_NE(frames.description.find("robot diff_drive"), std::string::npos);
  EXPECT_FALSE(world.robot("rover")->execute(robot::CraneTarget{0.1, 0.1, 0.1},
                                             world.time()));  // it has no crane
}

TEST(DiffDriveRobot, ItsStateIsSavedAndRestoredWithTheWorlds) {
  World world(rover_world(kWall));
  drive(world, "rover", 0.3, 0.2, 1.0);
  const WorldSnapshot saved = world.snapshot();
  const WorldState at_save = world.state();
  drive(world, "rover", 0.3, -0.4, 1.0);
  const WorldState first = world.state();
  ASSERT_NE(first.robots, at_save.robots);
  ASSERT_TRUE(world.restore(saved).ok());
  // Its own part (commands, wheels, odometry, the last sweep) and its bodies, bit for bit.
  const WorldState restored = world.state();
  EXPECT_EQ(restored.robots, at_save.robots);
  EXPECT_EQ(serialize(restored), serialize(at_save));
  // And the continuation is the first one, bit for bit.
  drive(world, "rover", 0.3, -0.4, 1.0);
  EXPECT_EQ(serialize(world.state()), serialize(first));
}

TEST(DiffDriveRobot, DamagedStateIsRefusedAndChangesNothing) {
  World world(rover_world());
  drive(world, "rover", 0.3, 0.0, 0.5);
  const uint64_t before = world.state_hash();
  WorldState state = world.state();
  ASSERT_EQ(state.robots.size(), 1u);
  state.robots[0].resize(state.robots[0].size() / 2);  // truncated
  const Status status = world.restore({world.fingerprint(), serialize(state)});
  EXPECT_EQ(status.code, ErrorCode::InvalidArgument);
  EXPECT_NE(status.message.find("robot 'rover'"), std::string::npos) << status.message;
  EXPECT_EQ(world.state_hash(), before);
}

}  // namespace
}  // namespace macsim
