// The simulated KURT3D in ODE: it stands, drives, turns, stops on timeout, and its
// encoder odometry agrees with the ground truth.
#include "macsim/sim_core/kurt_robot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world_loader.h"
#include "support/world_helpers.h"

namespace macsim {
namespace {

using test::run_for;
using test::yaw_of;

WorldSpec flat_world() {
  return load_world_string(R"(<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE>
      <POS>0,0,0</POS></ROBOT></WORLD>)",
                           "flat.xml");
}

// The KURT of these worlds driven as a controller drives it: the twist every 0.1 s.
void drive(World& world, double linear, double angular, double seconds) {
  test::drive(world, "kurt", linear, angular, seconds);
}

TEST(KurtRobot, RestsOnItsWheels) {
  World world(flat_world());
  run_for(world, 1.0);
  const KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  const Pose p = kurt.base_footprint_pose();
  EXPECT_NEAR(p.position.z(), 0.0, 0.005);  // sinks at most a few mm into the soft contact
  EXPECT_NEAR(p.position.x(), 0.0, 1e-3);
  EXPECT_NEAR(p.position.y(), 0.0, 1e-3);
  EXPECT_LT(kurt.linear_velocity().norm(), 1e-3);
  EXPECT_EQ(kurt.odometry().x, 0.0);
}

TEST(KurtRobot, PositiveSpeedDrivesForwardAtTheCommandedSpeed) {
  World world(flat_world());
  run_for(world, 0.5);
  drive(world, 0.3, 0.0, 3.0);
  const KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  EXPECT_NEAR(kurt.linear_velocity().x(), 0.3, 0.01);
  const Pose p = kurt.base_footprint_pose();
  EXPECT_GT(p.position.x(), 0.85);  // 0.9 m minus the acceleration phase
  EXPECT_LT(p.position.x(), 0.91);
  EXPECT_NEAR(p.position.y(), 0.0, 0.01);
  EXPECT_NEAR(yaw_of(p), 0.0, 0.01);
}

TEST(KurtRobot, EncoderOdometryAgreesWithGroundTruthOnAStraightRun) {
  World world(flat_world());
  run_for(world, 0.5);
  const double x0 = world.robot("kurt")->base_footprint_pose().position.x();
  drive(world, 0.3, 0.0, 3.5);
  run_for(world, 1.0);
  const KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
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
  run_for(world, 1.0);
  EXPECT_EQ(world.robot_as<KurtRobot>("kurt")->state().frames, 100u);
}

TEST(KurtRobot, PositiveAngularTwistTurnsCounterClockwise) {
  World world(flat_world());
  run_for(world, 0.5);
  drive(world, 0.0, 0.5, 2.0);
  const KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  const Pose p = kurt.base_footprint_pose();
  EXPECT_GT(yaw_of(p), 0.3);
  EXPECT_LT(p.position.head<2>().norm(), 0.05);  // turns in place
  EXPECT_GT(kurt.odometry().yaw, 0.0);
}

TEST(KurtRobot, StopsWhenCommandsStopForTheTimeout) {
  World world(flat_world());
  run_for(world, 0.5);
  KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  kurt.command_twist(0.4, 0.0, world.time());
  run_for(world, 0.55);
  EXPECT_DOUBLE_EQ(kurt.state().active.left, 0.4);  // still within 0.6 s
  run_for(world, 0.1);
  EXPECT_EQ(kurt.state().active.left, 0.0);  // 0.65 s after the command
  EXPECT_EQ(kurt.state().active.right, 0.0);
  run_for(world, 0.5);
  EXPECT_LT(kurt.linear_velocity().norm(), 0.01);
}

TEST(KurtRobot, SeveralRobotsShareAWorldAndObeyTheirOwnCommands) {
  World world(load_world_string(R"(<WORLD>
      <ROBOT><ID>alpha</ID><TYPE>kurt3d</TYPE><POS>0,0,0</POS></ROBOT>
      <ROBOT><ID>beta</ID><TYPE>kurt2</TYPE><POS>0,2,0</POS><ROT>0,0,90</ROT></ROBOT></WORLD>)",
                                "two.xml"));
  ASSERT_EQ(world.robots().size(), 2u);
  EXPECT_TRUE(world.robot_as<KurtRobot>("alpha")->config().crane);
  EXPECT_FALSE(world.robot_as<KurtRobot>("beta")->config().crane);
  for (int i = 0; i < 2000; ++i) {
    if (i % 100 == 0) world.robot("beta")->execute(robot::Twist{0.3, 0.0}, world.time());
    world.step();
  }
  EXPECT_LT(world.robot("alpha")->base_footprint_pose().position.head<2>().norm(), 0.01);
  // beta faces +y: it drove along y.
  const Eigen::Vector3d beta = world.robot("beta")->base_footprint_pose().position;
  EXPECT_GT(beta.y(), 2.4);
  EXPECT_NEAR(beta.x(), 0.0, 0.05);
  EXPECT_GT(world.robot("beta")->odometry().x, 0.4);  // its own odometry frame: forward is x
}

TEST(KurtRobot, UnknownRobotTypesAreNamedWithTheKnownOnes) {
  try {  // refused when the file is loaded, not only when the world is built
    load_world_string("<WORLD>\n<ROBOT><ID>r</ID><TYPE>kurt9</TYPE></ROBOT></WORLD>", "w.xml");
    FAIL();
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("known: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("kurt3d"), std::string::npos) << e.what();
  }
}

TEST(KurtRobot, EncoderRateSetsHowOftenFramesComeAndIsChecked) {
  World fast(load_world_string(
      "<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE><ENCODER_RATE>1000</ENCODER_RATE></ROBOT>"
      "</WORLD>",
      "fast.xml"));
  World standard(load_world_string("<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT></WORLD>",
                                   "standard.xml"));
  for (int i = 0; i < 100; ++i) {
    fast.robot("kurt")->execute(robot::Twist{0.3, 0.0}, fast.time());
    standard.robot("kurt")->execute(robot::Twist{0.3, 0.0}, standard.time());
    fast.step();
    standard.step();
  }
  EXPECT_NEAR(static_cast<double>(fast.robot_as<KurtRobot>("kurt")->state().frames), 100.0, 1.0);
  EXPECT_NEAR(static_cast<double>(standard.robot_as<KurtRobot>("kurt")->state().frames), 10.0, 1.0);
  // The odometry integrates with the frame period as its time step: both see the same motion.
  EXPECT_NEAR(fast.robot("kurt")->odometry().x, standard.robot("kurt")->odometry().x, 0.005);
  EXPECT_GT(fast.robot("kurt")->odometry().x, 0.01);
  try {
    load_world_string(
        "<WORLD>\n<ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE>\n"
        "<ENCODER_RATE>-5</ENCODER_RATE></ROBOT></WORLD>",
        "bad.xml");
    FAIL() << "a negative encoder rate was accepted";
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("ENCODER_RATE"), std::string::npos) << e.what();
  }
}

// Drives at 0.3 m/s towards a 0.2 m high ramp of `degrees`; returns the highest footprint z.
double climb(const std::string& type, double degrees) {
  World world(load_world_string("<WORLD><ROBOT><ID>kurt</ID><TYPE>" + type +
                                    "</TYPE></ROBOT><RAMP><ID>r</ID><POS>0.6,0,0</POS><WIDTH>1"
                                    "</WIDTH><HEIGHT>0.2</HEIGHT><ANGLE>" +
                                    std::to_string(degrees) + "</ANGLE></RAMP></WORLD>",
                                "ramp.xml"));
  KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  double highest = 0;
  for (int i = 0; i < 10000; ++i) {
    if (i % 100 == 0) kurt.command_twist(0.3, 0.0, world.time());
    world.step();
    highest = std::max(highest, kurt.base_footprint_pose().position.z());
  }
  return highest;
}

TEST(KurtRobot, ClimbsAFifteenDegreeRamp) {
  EXPECT_GT(climb("kurt3d", 15), 0.195);  // reaches the top edge at 0.2 m
}

TEST(KurtRobot, WheelTorqueLimitsTheSlopeItCanClimb) {
  // With 1 N m per wheel the six motors push 6 / 0.0603 = 99.5 N; the 19.7 kg robot needs
  // m g sin(theta) of it on a slope: the limit is asin(99.5 / 193) = 31 degrees.
  KurtConfig weak = *find_kurt_type("kurt3d");
  weak.body.wheel_torque = 1.0;
  register_kurt_type("kurt3d_weak_motors", weak);
  EXPECT_GT(climb("kurt3d_weak_motors", 20), 0.195);
  EXPECT_LT(climb("kurt3d_weak_motors", 36), 0.1);  // stalls on the slope
  // The shipped robot (4 N m per wheel, mu 1) climbs 40 degrees; friction and tipping, not
  // torque, stop it at 45.
  EXPECT_GT(climb("kurt3d", 40), 0.195);
}

TEST(KurtRobot, OdometryErrorOverAMetreSquareIsWhatTheSlipFactorPredicts) {
  World world(flat_world());
  run_for(world, 0.5);
  KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
  // How much does this robot skid when it turns? Turning in place at w = 0.4 commands wheel
  // speeds -+0.28 w: kinematically 2 w; the true rate over the kinematic one is the slip.
  drive(world, 0.0, 0.4, 1.0);  // spin up
  const double yaw_before = yaw_of(kurt.base_footprint_pose());
  drive(world, 0.0, 0.4, 2.0);
  const double slip =
      std::remainder(yaw_of(kurt.base_footprint_pose()) - yaw_before, 2 * M_PI) / (2 * 0.4 * 2.0);
  EXPECT_NEAR(slip, 0.69, 0.1);  // the order of the real robot's turning adaptation (0.65 here)
  kurt.command_twist(0.0, 0.0, world.time());
  run_for(world, 0.5);
  const PlanarOdometry origin = kurt.odometry();
  const Eigen::Vector2d start_position = kurt.base_footprint_pose().position.head<2>();
  // Drive a 1 m square by odometry: straight 1 m, turn +90 degrees, four times.
  double true_turn = 0, last_yaw = yaw_of(kurt.base_footprint_pose());
  auto track = [&] {
    const double yaw = yaw_of(kurt.base_footprint_pose());
    true_turn += std::remainder(yaw - last_yaw, 2 * M_PI);
    last_yaw = yaw;
  };
  for (int side = 0; side < 4; ++side) {
    const PlanarOdometry start = kurt.odometry();
    while (std::hypot(kurt.odometry().x - start.x, kurt.odometry().y - start.y) < 1.0) {
      kurt.command_twist(0.3, 0.0, world.time());
      world.step();
      track();
    }
    const double heading = start.yaw + M_PI / 2;
    while (std::remainder(heading - kurt.odometry().yaw, 2 * M_PI) > 0) {
      kurt.command_twist(0.0, 0.4, world.time());
      world.step();
      track();
    }
    kurt.command_twist(0.0, 0.0, world.time());
    run_for(world, 0.5);
    track();
  }
  // Odometry scales turns by the driver's 0.69 where the robot, turning steadily, really turns
  // by `slip`: the square's 2 pi of turning can be off by at most about 2 pi |1 - slip / 0.69|
  // (starting and stopping each turn skid differently, which only narrows the gap).
  const double predicted = std::fabs(2 * M_PI * (1 - slip / 0.69));
  const double heading_error = std::fabs(2 * M_PI - true_turn);
  EXPECT_LT(heading_error, predicted + 0.05) << "slip " << slip;
  const Eigen::Vector2d end = kurt.base_footprint_pose().position.head<2>();
  EXPECT_LT((end - start_position).norm(), 0.35);
  EXPECT_NEAR(kurt.odometry().x, origin.x, 0.05);  // odometry believes it closed the square
  EXPECT_NEAR(kurt.odometry().y, origin.y, 0.05);
}

}  // namespace
}  // namespace macsim
