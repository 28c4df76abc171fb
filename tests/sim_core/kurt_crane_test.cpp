// The crane arm with its electromagnet: what it lifts, what it cannot, what it never holds.
#include <gtest/gtest.h>

#include "macsim/sim_core/kurt_robot.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

// The magnet hangs 0.55 m ahead of base_link: a can there is under it.
const Eigen::Vector3d kUnderMagnet(0.55, 0.0, 0.0);

class Crane : public ::testing::Test {
 protected:
  // A robot and a bubble-top can of `density` under its magnet.
  void load(double density, bool magnetizable, const std::string& type = "kurt3d") {
    world = std::make_unique<World>(load_world_string(
        "<WORLD><ROBOT><ID>kurt</ID><TYPE>" + type + "</TYPE></ROBOT></WORLD>", "crane.xml"));
    ObjectSpec can;
    can.name = "can";
    can.components = {{Shape::Cylinder, {0.033, 0, 0.115}, at(0, 0, 0.0575), {0.8f, 0.1f, 0.1f, 1.0f}, ""},
                      {Shape::Sphere, {0.02, 0, 0}, at(0, 0, 0.115), {0.8f, 0.8f, 0.8f, 1.0f}, ""}};
    can.pose.position = kUnderMagnet;
    can.density = density;
    can.magnetizable = magnetizable;
    auto id = world->edit().create_object(can);
    ASSERT_TRUE(id.ok()) << id.status.message;
    can_id = id.value;
    kurt = world->robot_as<KurtRobot>("kurt");
    run_for(*world, 0.5);
  }

  double can_z() { return world->objects().object_state(can_id).value.pose.position.z(); }

  // Lowers the magnet onto the can's top, switches it on, hoists back up.
  void pick() {
    kurt->command_crane({0.0, 0.0, 0.2});  // deeper than the can's top: the hoist presses on it
    run_for(*world, 2.0);
    kurt->command_magnet(true);
    run_for(*world, 0.2);
    kurt->command_crane({0.0, 0.0, 0.0});
    run_for(*world, 2.5);
  }

  bool event(WorldEvent::Type type) {
    for (const auto& e : world->take_events()) {
      if (e.type == type) return true;
    }
    return false;
  }

  std::unique_ptr<World> world;
  KurtRobot* kurt = nullptr;
  ObjectId can_id = 0;
};

TEST_F(Crane, LiftsALightMagnetizableCanCarriesItAndDropsItOnATarget) {
  load(190, true);  // a tin can: 0.08 kg
  pick();
  EXPECT_TRUE(event(WorldEvent::Type::ObjectAttached));
  EXPECT_EQ(kurt->crane_state().held_object, "can");
  EXPECT_GT(can_z(), 0.1);  // in the air
  // Carry it: slew a quarter turn to the left and let go above the target.
  kurt->command_crane({M_PI / 2, 0.0, 0.0});
  run_for(*world, 3.0);
  const Eigen::Vector3d target = kurt->magnet_pose().position;
  kurt->command_magnet(false);
  run_for(*world, 1.5);
  EXPECT_TRUE(event(WorldEvent::Type::ObjectReleased));
  EXPECT_TRUE(kurt->crane_state().held_object.empty());
  const Eigen::Vector3d landed = world->objects().object_state(can_id).value.pose.position;
  EXPECT_NEAR(landed.x(), target.x(), 0.06);
  EXPECT_NEAR(landed.y(), target.y(), 0.06);
  EXPECT_GT(landed.y(), 0.35);          // carried well to the robot's left
  EXPECT_LT(landed.z(), 0.04);          // on the floor again (standing, or fallen over)
}

TEST_F(Crane, ACanTooHeavyForTheHoistIsHeldButNotLifted) {
  load(4700, true);  // a lead can: 2.0 kg, far beyond the hoist's 7 N
  pick();
  EXPECT_TRUE(event(WorldEvent::Type::ObjectAttached));  // the magnet holds it ...
  EXPECT_LT(can_z(), 0.005);                             // ... the motor cannot lift it
  EXPECT_GT(kurt->crane_state().hoist, 0.1);             // the hoist stays down
}

TEST_F(Crane, ANonMagnetizableCanIsNeverAttached) {
  load(150, false);  // a plastic can
  pick();
  EXPECT_FALSE(event(WorldEvent::Type::ObjectAttached));
  EXPECT_TRUE(kurt->crane_state().held_object.empty());
  EXPECT_LT(can_z(), 0.005);
}

TEST_F(Crane, TheMagnetLetsGoAboveItsHoldingForce) {
  KurtConfig weak = *find_kurt_type("kurt3d");
  weak.crane_params.holding_force = 3.0;  // N: less than a 0.45 kg can weighs
  register_kurt_type("kurt3d_weak_magnet", weak);
  load(0.45 / (M_PI * 0.033 * 0.033 * 0.115 + 4.0 / 3 * M_PI * std::pow(0.02, 3)), true,
       "kurt3d_weak_magnet");
  pick();
  bool overload = false;
  for (const auto& e : world->take_events()) {
    overload |= e.type == WorldEvent::Type::ObjectReleased && e.detail.find("overload") != std::string::npos;
  }
  EXPECT_TRUE(overload);
  EXPECT_LT(can_z(), 0.02);
}

TEST_F(Crane, DestroyingTheHeldObjectReleasesIt) {
  load(190, true);
  pick();
  ASSERT_EQ(kurt->crane_state().held_object, "can");
  ASSERT_TRUE(world->edit().destroy_object(can_id).ok());
  EXPECT_TRUE(kurt->crane_state().held_object.empty());
  run_for(*world, 0.5);  // and nothing dangles
}

TEST_F(Crane, AHeldObjectIsPartOfTheSnapshot) {
  load(190, true);
  pick();
  const WorldSnapshot held = world->snapshot();
  kurt->command_magnet(false);
  run_for(*world, 1.0);
  ASSERT_TRUE(world->restore(held).ok());
  kurt = world->robot_as<KurtRobot>("kurt");
  EXPECT_EQ(kurt->crane_state().held_object, "can");
  run_for(*world, 1.0);
  EXPECT_GT(can_z(), 0.1);  // still up on the magnet
}

}  // namespace
}  // namespace macsim::test
