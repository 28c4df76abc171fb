// The automatic door and its weight-triggered switch (seed section 2.5).
#include <gtest/gtest.h>

#include <algorithm>

#include "support/world_helpers.h"

namespace macsim::test {
namespace {

constexpr double kG = 9.81;

class DoorSwitch : public ::testing::Test {
 protected:
  World world{shipped_world("DemoWorld_v1.xml")};
  DoorParts parts = world.doors().door_parts(0).value;

  double platform_mass() { return world.objects().object_mass(*parts.platform).value; }

  // Sets a 5 cm cube of `mass` kg gently on the platform, lets it settle for `seconds`.
  void load_platform(double mass, double seconds) {
    run_for(world, 0.2);
    const Eigen::Vector3d top = world.objects().object_state(*parts.platform).value.pose.position +
                                Eigen::Vector3d(0, 0, 0.070 + 0.025 + 0.001);
    ObjectSpec cube = primitive(Shape::Box, Eigen::Vector3d::Constant(0.05), top);
    cube.density = mass / (0.05 * 0.05 * 0.05);
    ASSERT_TRUE(world.edit().create_object(cube).ok());
    run_for(world, seconds);
  }
};

TEST_F(DoorSwitch, TheDemoDoorIsFoundByTheSeedsNamingConvention) {
  ASSERT_EQ(world.doors().door_count(), 1);
  EXPECT_EQ(world.doors().door_name(0), "doors/door_00");
  EXPECT_EQ(world.doors().find_door("doors/door_00"), 0);
  EXPECT_EQ(world.objects().object(parts.leaf)->name, "doors/door_00/door_component/leaf");
  EXPECT_EQ(world.objects().object(parts.leaf)->kind, ObjectKind::DoorLeaf);
  EXPECT_EQ(world.objects().object(*parts.platform)->kind, ObjectKind::SwitchPlatform);
  EXPECT_EQ(world.objects().object(*parts.base)->kind, ObjectKind::SwitchBase);
  EXPECT_EQ(world.objects().object(parts.frame)->kind, ObjectKind::DoorFrame);
}

TEST_F(DoorSwitch, TriggerMassIsMaxForceOverGMinusThePlatform) {
  // MAX_FORCE 0.5 N carries 0.5 / 9.81 = 0.051 kg, of which the platform weighs 0.002 kg.
  const double threshold = 0.5 / kG - platform_mass();
  EXPECT_NEAR(threshold, 0.049, 0.001);
  EXPECT_NEAR(platform_mass(), 0.002, 1e-12);
}

TEST_F(DoorSwitch, ABoxTwentyPercentUnderTheThresholdLeavesTheDoorShut) {
  load_platform(0.8 * (0.5 / kG - platform_mass()), 4.0);
  const DoorState state = world.doors().door_state(0).value;
  EXPECT_FALSE(state.triggered);
  EXPECT_LT(state.switch_travel, 0.5);
  EXPECT_EQ(state.gap, DoorGap::Closed);
  EXPECT_LT(state.opening, 0.01);
}

TEST_F(DoorSwitch, ABoxTwentyPercentOverTheThresholdOpensTheDoor) {
  load_platform(1.2 * (0.5 / kG - platform_mass()), 4.0);
  const DoorState state = world.doors().door_state(0).value;
  EXPECT_TRUE(state.triggered);
  EXPECT_FALSE(state.virtually_triggered);
  EXPECT_GT(state.switch_travel, 0.9);
  EXPECT_EQ(state.gap, DoorGap::Open);
  // The leaf slid 0.85 m along the wall (+y).
  EXPECT_NEAR(world.objects().object_state(parts.leaf).value.pose.position.y(), 0.85, 0.01);
  bool triggered = false, opened = false;
  for (const auto& e : world.take_events()) {
    triggered |= e.type == WorldEvent::Type::SwitchTriggered && e.subject == "doors/door_00";
    opened |= e.type == WorldEvent::Type::DoorOpened;
  }
  EXPECT_TRUE(triggered);
  EXPECT_TRUE(opened);
}

TEST_F(DoorSwitch, DoorPassesThroughHalfOpenAndClosesWhenTheLoadGoes) {
  ASSERT_TRUE(world.doors().set_switch_triggered(0, true).ok());
  run_for(world, 1.0);  // 0.3 m/s for 1 s: about a third of 0.85 m
  EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Half);
  run_for(world, 3.0);
  EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Open);
  ASSERT_TRUE(world.doors().set_switch_triggered(0, false).ok());
  run_for(world, 4.0);
  EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Closed);
  EXPECT_FALSE(world.doors().door_state(0).value.triggered);
}

TEST_F(DoorSwitch, VirtualTriggerOpensTheDoorWithoutPressingTheSwitch) {
  ASSERT_TRUE(world.doors().set_switch_triggered(0, true).ok());
  run_for(world, 4.0);
  const DoorState state = world.doors().door_state(0).value;
  EXPECT_TRUE(state.triggered);
  EXPECT_TRUE(state.virtually_triggered);
  EXPECT_LT(state.switch_travel, 0.1);  // the platform stays up
  EXPECT_EQ(state.gap, DoorGap::Open);
}

TEST_F(DoorSwitch, MovingTheSwitchMovesItsBaseAlongAndItStillWorks) {
  const Eigen::Vector3d base0 = world.objects().object_state(*parts.base).value.pose.position;
  const Eigen::Vector3d platform0 = world.objects().object_state(*parts.platform).value.pose.position;
  const Eigen::Vector3d target = platform0 + Eigen::Vector3d(-0.5, -1.5, 0);
  ASSERT_TRUE(world.doors().set_switch_position(0, target).ok());
  EXPECT_TRUE(world.objects().object_state(*parts.platform).value.pose.position.isApprox(target, 1e-9));
  EXPECT_TRUE(world.objects().object_state(*parts.base).value.pose.position.isApprox(
      base0 + (target - platform0), 1e-9));
  load_platform(0.1, 4.0);
  EXPECT_TRUE(world.doors().door_state(0).value.triggered);
  EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Open);
}

TEST_F(DoorSwitch, MovingTheDoorMovesItsFrameAlongAndItStillSlides) {
  const Eigen::Vector3d frame0 = world.objects().object_state(parts.frame).value.pose.position;
  const Eigen::Vector3d leaf0 = world.objects().object_state(parts.leaf).value.pose.position;
  const Eigen::Vector3d delta(-0.3, 0.0, 0.0);
  ASSERT_TRUE(world.doors().set_door_position(0, leaf0 + delta).ok());
  EXPECT_TRUE(world.objects().object_state(parts.frame).value.pose.position.isApprox(frame0 + delta, 1e-9));
  ASSERT_TRUE(world.doors().set_switch_triggered(0, true).ok());
  run_for(world, 4.0);
  const Eigen::Vector3d leaf = world.objects().object_state(parts.leaf).value.pose.position;
  EXPECT_NEAR(leaf.x(), leaf0.x() + delta.x(), 1e-3);
  EXPECT_NEAR(leaf.y(), leaf0.y() + 0.85, 0.01);
}

TEST_F(DoorSwitch, DoorPartsCannotBeMovedOneByOne) {
  const Status s = world.edit().set_position(parts.leaf, {0, 0, 1});
  EXPECT_EQ(s.code, ErrorCode::NotApplicable);
  EXPECT_NE(s.message.find("set_door_position"), std::string::npos);
}

/// The stiff-switch family with its switch's motor force at `force` and `cans` of its tin cans
/// stood side by side on the platform; whether the door opened after `seconds`.
bool stiff_switch_opens(double force, int cans, double seconds = 3.0) {
  WorldSpec spec = shipped_world("goals/stiff_switch.xml");
  for (auto& joint : spec.joints)
    if (joint.name.size() >= 13 && joint.name.substr(joint.name.size() - 13) == "BUTTON_SLIDER") joint.max_force = force;
  const Eigen::Vector3d platform = spec.object("doors/door_00/switch_component/platform")->pose.position;
  const char* tins[] = {"environment_00/can_00", "environment_00/can_01"};
  for (int k = 0; k < cans; ++k) {
    auto it = std::find_if(spec.objects.begin(), spec.objects.end(), [&](const ObjectSpec& o) { return o.name == tins[k]; });
    it->pose.position = platform + Eigen::Vector3d(0, k == 0 ? -0.045 : 0.045, 0.071);
  }
  World world(std::move(spec));
  run_for(world, seconds);
  return world.doors().door_state(0).value.triggered;
}

TEST(StiffSwitchFamily, OneTinCanLeavesItUpAndTwoPressItAcrossTheFamilysRange) {
  const WorldSpec spec = shipped_world("goals/stiff_switch.xml");
  ASSERT_EQ(spec.variation->joint_forces.size(), 1u);
  for (double force : {spec.variation->joint_forces[0].lo, spec.variation->joint_forces[0].hi}) {
    EXPECT_FALSE(stiff_switch_opens(force, 1)) << force << " N";
    EXPECT_TRUE(stiff_switch_opens(force, 2)) << force << " N";
  }
  // The demonstrator's switch (0.5 N) sinks under one.
  EXPECT_TRUE(stiff_switch_opens(0.5, 1));
}

/// The push-to-switch family with its two boxes set down at `offsets` from the flush plate's
/// middle; after `seconds`, how far each moved and whether the door opened.
std::pair<std::vector<double>, bool> boxes_on_flush_plate(const std::vector<Eigen::Vector2d>& offsets,
                                                          double seconds = 4.0) {
  WorldSpec spec = shipped_world("goals/push_to_switch.xml");
  const Eigen::Vector3d plate = spec.object("doors/door_00/switch_component/platform")->pose.position;
  const char* boxes[] = {"environment_00/box_00", "environment_00/box_01"};
  std::vector<Eigen::Vector3d> placed;
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    auto it = std::find_if(spec.objects.begin(), spec.objects.end(),
                           [&](const ObjectSpec& o) { return o.name == boxes[k]; });
    it->pose.position = Eigen::Vector3d(plate.x() + offsets[k].x(), plate.y() + offsets[k].y(), 0.0065);
    placed.push_back(it->pose.position);
  }
  World world(std::move(spec));
  run_for(world, seconds);
  std::vector<double> moved;
  for (std::size_t k = 0; k < offsets.size(); ++k)
    moved.push_back((world.objects().object_state(id_of(world, boxes[k])).value.pose.position - placed[k])
                        .head<2>()
                        .norm());
  return {moved, world.doors().door_state(0).value.triggered};
}

TEST(FlushSwitch, ABoxOnThePlatePressesItAndOneAcrossItsEdgeStaysWhereItWasPut) {
  // Whole on the plate: pressed, and it stays.
  auto [moved, triggered] = boxes_on_flush_plate({{0.0, 0.0}});
  EXPECT_TRUE(triggered);
  EXPECT_LT(moved[0], 0.01);
  // Across an edge (half on a ramp), and near a corner: nothing throws it off.
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(-0.24, 0.1), Eigen::Vector2d(0.1, 0.26),
                                     Eigen::Vector2d(0.2, -0.2)}) {
    std::tie(moved, triggered) = boxes_on_flush_plate({at});
    EXPECT_LT(moved[0], 0.02) << at.transpose();
  }
  // Beside it on the floor: not pressed.
  std::tie(moved, triggered) = boxes_on_flush_plate({{0.5, 0.0}});
  EXPECT_FALSE(triggered);
}

TEST(DoorOrientation, ARotatedDoorSwitchStructureWorksAlongItsOwnAxes) {
  World world(shipped_world("DemoWorld_v1.xml"));
  // A second door-switch structure turned by -90 degrees: its leaf slides along world +x.
  const Pose pose{{-2.6, -0.4, 0}, Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()))};
  auto ids = world.edit().import_environment(source("worlds/DemoEnvironment_v1/doors/door_switch.xml"),
                                      "door_01", pose);
  ASSERT_TRUE(ids.ok()) << ids.status.message;
  const int door = *world.doors().find_door("door_01");
  const DoorParts parts = world.doors().door_parts(door).value;
  const Eigen::Vector3d leaf0 = world.objects().object_state(parts.leaf).value.pose.position;
  // Its switch is turned with it: 1 m in front of the door and 0.8 m aside, in its own frame.
  const Eigen::Vector3d platform = world.objects().object_state(*parts.platform).value.pose.position;
  EXPECT_TRUE(platform.isApprox(pose.position + pose.orientation * Eigen::Vector3d(-1.0, 0.8, 0), 1e-9));
  // Press it with 0.1 kg.
  ObjectSpec weight = primitive(Shape::Box, Eigen::Vector3d::Constant(0.05), platform + Eigen::Vector3d(0, 0, 0.097));
  weight.density = 0.1 / (0.05 * 0.05 * 0.05);
  ASSERT_TRUE(world.edit().create_object(weight).ok());
  run_for(world, 4.0);
  EXPECT_TRUE(world.doors().door_state(door).value.triggered);
  EXPECT_EQ(world.doors().door_state(door).value.gap, DoorGap::Open);
  const Eigen::Vector3d moved = world.objects().object_state(parts.leaf).value.pose.position - leaf0;
  EXPECT_TRUE(moved.isApprox(pose.orientation * Eigen::Vector3d(0, 0.85, 0), 0.02)) << moved.transpose();
  EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Closed);  // the other door is not involved
}

TEST(DoorHinge, AHingeJointInTheDoorFileMakesASwingingDoor) {
  const auto dir = temp_dir("hinge-door");
  write_file(dir / "door.xml", R"(<ENVIRONMENT>
    <OBJECT><ID>frame</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE><DIMS>0.06,0.06,0.7</DIMS><POS>0,-0.45,0.35</POS></OBJECT>
    <OBJECT><ID>leaf</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE><DIMS>0.04,0.8,0.6</DIMS><POS>0,0,0.32</POS><MASS>2</MASS></OBJECT>
    <JOINT><ID>DOOR_HINGE</ID><TYPE>HINGE</TYPE><BODY1>leaf</BODY1><BODY2>frame</BODY2>
      <ANCHOR>0,-0.42,0.32</ANCHOR><AXIS>0,0,1</AXIS><LO>0</LO><HI>90</HI><VELOCITY>1.0</VELOCITY><MAX_FORCE>20</MAX_FORCE></JOINT>
  </ENVIRONMENT>)");
  write_file(dir / "door_switch.xml", R"(<ENVIRONMENT>
    <IMPORT><ID>door_component</ID><NAME>door.xml</NAME></IMPORT></ENVIRONMENT>)");
  write_file(dir / "doors.xml", R"(<ENVIRONMENT>
    <IMPORT><ID>door_00</ID><NAME>door_switch.xml</NAME><POS>1,0,0</POS></IMPORT></ENVIRONMENT>)");
  write_file(dir / "world.xml", R"(<WORLD><IMPORT><ID>doors</ID><NAME>doors.xml</NAME></IMPORT></WORLD>)");
  World world(load_world_file((dir / "world.xml").string()));
  ASSERT_EQ(world.doors().door_count(), 1);
  EXPECT_FALSE(world.doors().door_parts(0).value.platform.has_value());  // a door without a switch
  ASSERT_TRUE(world.doors().set_switch_triggered(0, true).ok());
  run_for(world, 3.0);
  EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Open);
  // Swung 90 degrees about the hinge: the leaf's long side now points along x.
  const Pose leaf = world.objects().object_state(world.doors().door_parts(0).value.leaf).value.pose;
  const Eigen::Vector3d along = leaf.orientation * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(std::fabs(along.x()), 1.0, 0.02);
  EXPECT_NEAR(leaf.position.y(), -0.42, 0.02);
}

}  // namespace
}  // namespace macsim::test
