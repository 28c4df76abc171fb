// The simulated KURT3D in ODE: it stands, drives, turns, stops on timeout, and its
// encoder odometry agrees with the ground truth.
#include "macsim/sim_core/kurt_robot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "macsim/sim_core/simulation.h"
#include "macsim/sim_core/world_loader.h"

namespace macsim {
namespace {

WorldSpec flat_world() {
  return load_world_string(R"(<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE>
      <POS>0,0,0</POS></ROBOT></WORLD>)",
                           "flat.xml");
}

double yaw_of(const Pose& p) {
  const Eigen::Vector3d x = p.orientation * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

// Steps `seconds` of sim time, repeating the twist every 0.1 s like a controller would.
void drive(World& world, double linear, double angular, double seconds) {
  KurtRobot& kurt = *world.robot("kurt");
  const auto steps = static_cast<long>(std::llround(seconds / world.step_size()));
  for (long i = 0; i < steps; ++i) {
    if (i % 100 == 0) kurt.command_twist(linear, angular, world.time());
    world.step();
  }
}

void idle(World& world, double seconds) {
  const auto steps = static_cast<long>(std::llround(seconds / world.step_size()));
  for (long i = 0; i < steps; ++i) world.step();
}

TEST(KurtRobot, RestsOnItsWheels) {
  World world(flat_world());
  idle(world, 1.0);
  const KurtRobot& kurt = *world.robot("kurt");
  const Pose p = kurt.base_footprint_pose();
  EXPECT_NEAR(p.position.z(), 0.0, 0.005);  // sinks at most a few mm into the soft contact
  EXPECT_NEAR(p.position.x(), 0.0, 1e-3);
  EXPECT_NEAR(p.position.y(), 0.0, 1e-3);
  EXPECT_LT(kurt.linear_velocity().norm(), 1e-3);
  EXPECT_EQ(kurt.odometry().x, 0.0);
}

TEST(KurtRobot, PositiveSpeedDrivesForwardAtTheCommandedSpeed) {
  World world(flat_world());
  idle(world, 0.5);
  drive(world, 0.3, 0.0, 3.0);
  const KurtRobot& kurt = *world.robot("kurt");
  EXPECT_NEAR(kurt.linear_velocity().x(), 0.3, 0.01);
  const Pose p = kurt.base_footprint_pose();
  EXPECT_GT(p.position.x(), 0.85);  // 0.9 m minus the acceleration phase
  EXPECT_LT(p.position.x(), 0.91);
  EXPECT_NEAR(p.position.y(), 0.0, 0.01);
  EXPECT_NEAR(yaw_of(p), 0.0, 0.01);
}

TEST(KurtRobot, EncoderOdometryAgreesWithGroundTruthOnAStraightRun) {
  World world(flat_world());
  idle(world, 0.5);
  const double x0 = world.robot("kurt")->base_footprint_pose().position.x();
  drive(world, 0.3, 0.0, 3.5);
  idle(world, 1.0);
  const KurtRobot& kurt = *world.robot("kurt");
  const double truth = kurt.base_footprint_pose().position.x() - x0;
  const auto odom = kurt.odometry();
  // Rolling without slip on a rigid floor: the only error sources are the contact's
  // sinking (effective radius a fraction of a mm smaller) and the 17 um tick.
  EXPECT_NEAR(odom.x, truth, 0.01 * truth);
  EXPECT_NEAR(odom.y, 0.0, 1e-3);
  EXPECT_EQ(odom.linear, 0.0);  // standing still again
}

TEST(KurtRobot, EncoderFramesComeEveryTenMilliseconds) {
  World world(flat_world());
  idle(world, 1.0);
  EXPECT_EQ(world.robot("kurt")->odometry_frames(), 100u);
}

TEST(KurtRobot, PositiveAngularTwistTurnsCounterClockwise) {
  World world(flat_world());
  idle(world, 0.5);
  drive(world, 0.0, 0.5, 2.0);
  const KurtRobot& kurt = *world.robot("kurt");
  const Pose p = kurt.base_footprint_pose();
  EXPECT_GT(yaw_of(p), 0.3);
  EXPECT_LT(p.position.head<2>().norm(), 0.05);  // turns in place
  EXPECT_GT(kurt.odometry().yaw, 0.0);
}

TEST(KurtRobot, StopsWhenCommandsStopForTheTimeout) {
  World world(flat_world());
  idle(world, 0.5);
  KurtRobot& kurt = *world.robot("kurt");
  kurt.command_twist(0.4, 0.0, world.time());
  idle(world, 0.55);
  EXPECT_DOUBLE_EQ(kurt.active_wheel_speeds().left, 0.4);  // still within 0.6 s
  idle(world, 0.1);
  EXPECT_EQ(kurt.active_wheel_speeds().left, 0.0);  // 0.65 s after the command
  EXPECT_EQ(kurt.active_wheel_speeds().right, 0.0);
  idle(world, 0.5);
  EXPECT_LT(kurt.linear_velocity().norm(), 0.01);
}

}  // namespace
}  // namespace macsim
