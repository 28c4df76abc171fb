// The seed's Table 1, one test per cell: every supervisor operation on a portable basic,
// portable composite, fixed basic, fixed composite object, a ramp and a door, asserting the
// physical effect (or, where the operation has no physical meaning, a clear NotApplicable
// error that leaves the world unchanged).
#include <gtest/gtest.h>

#include "support/world_helpers.h"

namespace macsim::test {
namespace {

enum class Kind { PortableBasic, PortableComposite, FixedBasic, FixedComposite, Ramp, Door };

std::string kind_name(const ::testing::TestParamInfo<Kind>& info) {
  static const char* names[] = {"PortableBasic", "PortableComposite", "FixedBasic",
                                "FixedComposite", "Ramp", "Door"};
  return names[static_cast<int>(info.param)];
}

const Eigen::Vector3d kFreeSpot(-0.5, 0.3, 0.0);  // clear floor in the demo world

Eigen::Quaterniond yaw(double degrees) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d::UnitZ()));
}

class Table1 : public ::testing::TestWithParam<Kind> {
 protected:
  World world{shipped_world("DemoWorld_v1.xml")};

  Kind kind() const { return GetParam(); }
  bool portable() const { return kind() == Kind::PortableBasic || kind() == Kind::PortableComposite; }

  /// The demo world's object of this column (the leaf for the door).
  ObjectId subject() const {
    switch (kind()) {
      case Kind::PortableBasic: return id_of(world, "environment_01/box_red_small");
      case Kind::PortableComposite: return id_of(world, "environment_00/can_00");
      case Kind::FixedBasic: return id_of(world, "environment_01/post");
      case Kind::FixedComposite: return id_of(world, "environment_01/table");
      case Kind::Ramp: return id_of(world, "environment_02/ramp_00");
      case Kind::Door: return world.doors().door_parts(0).value.leaf;
    }
    return 0;
  }

  /// Drops a 4 cm ball above (x, y) and returns the height its centre settles at.
  double drop_ball_at(double x, double y) {
    auto ball = world.edit().create_object(primitive(Shape::Sphere, {0.04, 0, 0}, {x, y, 1.2}));
    EXPECT_TRUE(ball.ok()) << ball.status.message;
    return settled_z(world, ball.value, 1.5);
  }

  /// Would a 2 cm cube at `where` penetrate something? (Probes geometry without changing it.)
  bool occupied(const Eigen::Vector3d& where) {
    auto probe = world.edit().create_object(primitive(Shape::Box, Eigen::Vector3d::Constant(0.02), where),
                                     PenetrationPolicy::Refuse);
    if (probe.ok()) world.edit().destroy_object(probe.value);
    return probe.status.code == ErrorCode::Penetration;
  }

  /// Mass measured from the response to a 10 N push during one step, in free flight.
  double mass_by_impulse(ObjectId id) {
    EXPECT_TRUE(world.edit().set_pose(id, at(kFreeSpot.x(), kFreeSpot.y(), 1.5)).ok());
    EXPECT_TRUE(world.edit().set_linear_velocity(id, Eigen::Vector3d::Zero()).ok());
    EXPECT_TRUE(world.edit().set_angular_velocity(id, Eigen::Vector3d::Zero()).ok());
    EXPECT_TRUE(world.edit().add_force(id, {10, 0, 0}).ok());
    world.step();
    return 10 * world.step_size() / world.objects().object_state(id).value.linear_velocity.x();
  }

  /// Expects an operation on a fixed thing to be refused with NotApplicable, world unchanged.
  void expect_not_applicable(const Status& status, uint64_t hash_before) {
    EXPECT_EQ(status.code, ErrorCode::NotApplicable) << status.message;
    EXPECT_FALSE(status.message.empty());
    EXPECT_EQ(world.state_hash(), hash_before);
  }

  static ObjectSpec can(const Eigen::Vector3d& where) {
    ObjectSpec can;
    ComponentSpec body{Shape::Cylinder, {0.033, 0, 0.115}, at(0, 0, 0.0575), {0.5f, 0.5f, 0.5f, 1.0f}, ""};
    ComponentSpec top{Shape::Sphere, {0.02, 0, 0}, at(0, 0, 0.115), {0.5f, 0.5f, 0.5f, 1.0f}, ""};
    can.components = {body, top};
    can.pose.position = where;
    can.density = 190;
    return can;
  }
};

TEST_P(Table1, LoadFromXml) {
  const ObjectSpec* spec = world.objects().object(subject());
  ASSERT_NE(spec, nullptr);
  switch (kind()) {
    case Kind::PortableBasic:
      EXPECT_TRUE(spec->portable);
      EXPECT_EQ(spec->components.size(), 1u);
      EXPECT_NEAR(settled_z(world, subject()), 0.05, 0.002);  // rests on the floor
      break;
    case Kind::PortableComposite:
      EXPECT_TRUE(spec->portable);
      EXPECT_EQ(spec->components.size(), 2u);
      EXPECT_TRUE(spec->magnetizable);  // from <USER_APPS>
      EXPECT_NEAR(settled_z(world, subject()), 0.0, 0.002);
      break;
    case Kind::FixedBasic:
      EXPECT_FALSE(spec->portable);
      EXPECT_NEAR(drop_ball_at(0.0, -0.3), 0.4 + 0.04, 0.003);  // the post stands 0.4 m tall
      break;
    case Kind::FixedComposite:
      EXPECT_FALSE(spec->portable);
      EXPECT_EQ(spec->components.size(), 5u);
      EXPECT_NEAR(drop_ball_at(2.4, 1.2), 0.4 + 0.04, 0.003);   // on the table top
      break;
    case Kind::Ramp:
      ASSERT_TRUE(spec->ramp.has_value());
      EXPECT_NEAR(spec->ramp->height, 0.12, 1e-12);
      EXPECT_NEAR(spec->ramp->angle, 15 * M_PI / 180, 1e-12);
      EXPECT_NEAR(spec->ramp->depth(), 0.12 / std::tan(15 * M_PI / 180), 1e-12);
      EXPECT_TRUE(occupied({2.0 + spec->ramp->depth() / 2, -1.0, 0.03}));   // under the slope
      EXPECT_FALSE(occupied({2.0 + spec->ramp->depth() / 2, -1.0, 0.09}));  // above it
      break;
    case Kind::Door:
      EXPECT_EQ(world.doors().door_count(), 1);
      EXPECT_EQ(spec->kind, ObjectKind::DoorLeaf);
      EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Closed);
      break;
  }
}

TEST_P(Table1, CreateOnTheFly) {
  const int before = world.objects().object_count();
  Result<ObjectId> created;
  switch (kind()) {
    case Kind::PortableBasic:
      created = world.edit().create_object(primitive(Shape::Box, {0.1, 0.1, 0.1}, kFreeSpot + Eigen::Vector3d(0, 0, 0.5)));
      ASSERT_TRUE(created.ok());
      EXPECT_EQ(world.objects().object_count(), before + 1);
      EXPECT_NEAR(settled_z(world, created.value), 0.05, 0.002);
      break;
    case Kind::PortableComposite:
      created = world.edit().create_object(can(kFreeSpot + Eigen::Vector3d(0, 0, 0.3)));
      ASSERT_TRUE(created.ok()) << created.status.message;
      EXPECT_EQ(world.objects().object_count(), before + 1);
      EXPECT_NEAR(settled_z(world, created.value), 0.0, 0.002);  // stands on its bottom
      EXPECT_NEAR(world.objects().object_mass(created.value).value,
                  190 * (M_PI * 0.033 * 0.033 * 0.115 + 4.0 / 3 * M_PI * std::pow(0.02, 3)), 1e-12);
      break;
    case Kind::FixedBasic:
      created = world.edit().create_object(primitive(Shape::Box, {0.2, 0.2, 0.2}, kFreeSpot + Eigen::Vector3d(0, 0, 0.1), false));
      ASSERT_TRUE(created.ok());
      EXPECT_EQ(world.objects().object_count(), before + 1);
      EXPECT_NEAR(drop_ball_at(kFreeSpot.x(), kFreeSpot.y()), 0.2 + 0.04, 0.003);
      break;
    case Kind::FixedComposite: {
      ObjectSpec step = primitive(Shape::Box, {0.4, 0.4, 0.1}, kFreeSpot, false);
      step.components[0].pose.position.z() = 0.05;
      step.components.push_back({Shape::Box, {0.2, 0.2, 0.1}, at(0, 0, 0.15), {0.5f, 0.5f, 0.5f, 1.0f}, ""});
      created = world.edit().create_object(step);
      ASSERT_TRUE(created.ok()) << created.status.message;
      EXPECT_EQ(world.objects().object_count(), before + 1);
      EXPECT_NEAR(drop_ball_at(kFreeSpot.x(), kFreeSpot.y()), 0.2 + 0.04, 0.003);
      EXPECT_NEAR(drop_ball_at(kFreeSpot.x() + 0.15, kFreeSpot.y()), 0.1 + 0.04, 0.003);
      break;
    }
    case Kind::Ramp: {
      ObjectSpec ramp;
      ramp.ramp = RampGeometry{0.5, 0.1, 10 * M_PI / 180};
      ramp.pose.position = kFreeSpot;
      created = world.edit().create_object(ramp);
      ASSERT_TRUE(created.ok()) << created.status.message;
      EXPECT_EQ(world.objects().object_count(), before + 1);
      EXPECT_EQ(world.objects().object(created.value)->kind, ObjectKind::Ramp);
      const double mid = ramp.ramp->depth() / 2;
      EXPECT_TRUE(occupied(kFreeSpot + Eigen::Vector3d(mid, 0, 0.03)));
      EXPECT_FALSE(occupied(kFreeSpot + Eigen::Vector3d(mid, 0, 0.08)));
      break;
    }
    case Kind::Door: {
      auto ids = world.edit().import_environment(source("worlds/DemoEnvironment_v1/doors/door_switch.xml"),
                                          "door_01", at(-2.6, 0.5, 0));
      ASSERT_TRUE(ids.ok()) << ids.status.message;
      EXPECT_EQ(ids.value.size(), 4u);
      ASSERT_EQ(world.doors().door_count(), 2);
      ASSERT_TRUE(world.doors().set_switch_triggered(1, true).ok());
      run_for(world, 4.0);
      EXPECT_EQ(world.doors().door_state(1).value.gap, DoorGap::Open);
      EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Closed);
      EXPECT_EQ(world.objects().object_count(), before + 4);
      return;
    }
  }
  EXPECT_EQ(world.objects().index_of(created.value), before);  // appended to the list
}

TEST_P(Table1, DestroyOnTheFly) {
  const ObjectId id = subject();
  const int index = *world.objects().index_of(id);
  const ObjectId next = *world.objects().object_at(index + 1);
  const int before = world.objects().object_count();
  ASSERT_TRUE(world.edit().destroy_object(id).ok());
  EXPECT_EQ(world.objects().object(id), nullptr);
  EXPECT_EQ(world.edit().destroy_object(id).code, ErrorCode::UnknownObject);
  switch (kind()) {
    case Kind::PortableBasic:
    case Kind::PortableComposite:
      EXPECT_EQ(world.objects().object_count(), before - 1);
      EXPECT_EQ(world.objects().object_at(index), next);  // indices shift, ids stay
      break;
    case Kind::FixedBasic:
      EXPECT_NEAR(drop_ball_at(0.0, -0.3), 0.04, 0.003);  // falls to the floor now
      break;
    case Kind::FixedComposite:
      EXPECT_NEAR(drop_ball_at(2.4, 1.2), 0.04, 0.003);
      break;
    case Kind::Ramp:
      EXPECT_FALSE(occupied({2.2, -1.0, 0.03}));
      break;
    case Kind::Door:
      EXPECT_EQ(world.doors().door_count(), 0);          // the whole door-switch structure goes
      EXPECT_EQ(world.objects().object_count(), before - 4);
      break;
  }
}

TEST_P(Table1, ChangeDimensions) {
  const ObjectId id = subject();
  switch (kind()) {
    case Kind::PortableBasic: {
      Status s = world.edit().set_box_size(id, 0, {0.2, 0.2, 0.2}, PenetrationPolicy::Allow);
      ASSERT_TRUE(s.ok()) << s.message;
      EXPECT_EQ(s.penetrated, std::vector<std::string>{"ground"}) << s.penetrated.size();
      EXPECT_NEAR(world.objects().object_mass(id).value, 100 * 0.008, 1e-12);  // density kept
      EXPECT_NEAR(settled_z(world, id), 0.1, 0.003);
      EXPECT_EQ(world.edit().set_sphere_size(id, 0, 0.1).code, ErrorCode::WrongGeometry);
      break;
    }
    case Kind::PortableComposite: {
      const double density = world.objects().object(id)->density;
      ASSERT_TRUE(world.edit().set_cylinder_size(id, 0, 0.05, 0.115, PenetrationPolicy::Allow).ok());
      EXPECT_NEAR(world.objects().object_mass(id).value,
                  density * (M_PI * 0.05 * 0.05 * 0.115 + 4.0 / 3 * M_PI * std::pow(0.02, 3)), 1e-12);
      EXPECT_EQ(world.edit().set_box_size(id, 0, {0.1, 0.1, 0.1}).code, ErrorCode::WrongGeometry);
      EXPECT_EQ(world.edit().set_sphere_size(id, 2, 0.1).code, ErrorCode::InvalidArgument);  // no component 2
      EXPECT_NEAR(settled_z(world, id), 0.0, 0.003);
      break;
    }
    case Kind::FixedBasic:
      ASSERT_TRUE(world.edit().set_cylinder_size(id, 0, 0.06, 0.8, PenetrationPolicy::Allow).ok());
      EXPECT_NEAR(drop_ball_at(0.0, -0.3), 0.2 + 0.4 + 0.04, 0.003);  // centre 0.2, half 0.4
      break;
    case Kind::FixedComposite:
      ASSERT_TRUE(world.edit().set_box_size(id, 0, {1.0, 0.4, 0.03}).ok());
      EXPECT_NEAR(drop_ball_at(2.4 + 0.45, 1.2), 0.4 + 0.04, 0.003);  // beyond the old top
      break;
    case Kind::Ramp: {
      const RampGeometry steeper{0.8, 0.2, 20 * M_PI / 180};
      ASSERT_TRUE(world.edit().set_ramp(id, steeper, PenetrationPolicy::Allow).ok());
      const ObjectSpec& spec = *world.objects().object(id);
      EXPECT_NEAR(spec.ramp->height, 0.2, 1e-12);
      EXPECT_NEAR(spec.ramp->depth(), 0.2 / std::tan(20 * M_PI / 180), 1e-12);
      EXPECT_NEAR(spec.components[0].size.x(), steeper.length(), 1e-12);
      const double mid = steeper.depth() / 2;
      EXPECT_TRUE(occupied({2.0 + mid, -1.0, 0.08}));   // the surface rose to 0.1 here
      EXPECT_EQ(world.edit().set_box_size(id, 0, {1, 1, 1}).code, ErrorCode::WrongGeometry);
      break;
    }
    case Kind::Door:
      ASSERT_TRUE(world.edit().set_box_size(id, 0, {0.04, 0.84, 0.4}).ok());
      EXPECT_EQ(world.objects().object(id)->components[0].size, Eigen::Vector3d(0.04, 0.84, 0.4));
      ASSERT_TRUE(world.doors().set_switch_triggered(0, true).ok());
      run_for(world, 4.0);
      EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Open);  // still slides
      break;
  }
}

TEST_P(Table1, ChangePosition) {
  const ObjectId id = subject();
  const Eigen::Vector3d target = kFreeSpot + Eigen::Vector3d(0, 0, kind() == Kind::FixedBasic ? 0.2 : 0.0);
  switch (kind()) {
    case Kind::PortableBasic:
    case Kind::PortableComposite: {
      const Eigen::Vector3d up = kFreeSpot + Eigen::Vector3d(0, 0, 0.3);
      ASSERT_TRUE(world.edit().set_position(id, up).ok());
      EXPECT_TRUE(world.objects().object_state(id).value.pose.position.isApprox(up, 1e-12));
      run_for(world, 1.5);
      EXPECT_LT((world.objects().object_state(id).value.pose.position.head<2>() - kFreeSpot.head<2>()).norm(), 0.01);
      break;
    }
    case Kind::FixedBasic:
      ASSERT_TRUE(world.edit().set_position(id, target).ok());
      EXPECT_NEAR(drop_ball_at(kFreeSpot.x(), kFreeSpot.y()), 0.44, 0.003);
      EXPECT_NEAR(drop_ball_at(0.0, -0.3), 0.04, 0.003);  // nothing where it stood
      break;
    case Kind::FixedComposite:
      ASSERT_TRUE(world.edit().set_position(id, target).ok());
      EXPECT_NEAR(drop_ball_at(kFreeSpot.x(), kFreeSpot.y()), 0.44, 0.003);
      break;
    case Kind::Ramp: {
      ASSERT_TRUE(world.edit().set_position(id, target).ok());
      const double mid = world.objects().object(id)->ramp->depth() / 2;
      EXPECT_TRUE(occupied(kFreeSpot + Eigen::Vector3d(mid, 0, 0.03)));
      EXPECT_FALSE(occupied({2.0 + mid, -1.0, 0.03}));
      break;
    }
    case Kind::Door: {
      const Eigen::Vector3d leaf = world.objects().object_state(id).value.pose.position;
      ASSERT_TRUE(world.doors().set_door_position(0, leaf + Eigen::Vector3d(-0.2, 0, 0)).ok());
      EXPECT_NEAR(world.objects().object_state(id).value.pose.position.x(), leaf.x() - 0.2, 1e-9);
      EXPECT_EQ(world.edit().set_position(id, target).code, ErrorCode::NotApplicable);
      break;
    }
  }
}

TEST_P(Table1, ChangeOrientation) {
  const ObjectId id = subject();
  switch (kind()) {
    case Kind::PortableBasic: {
      ASSERT_TRUE(world.edit().set_orientation(id, yaw(45)).ok());
      run_for(world, 1.0);
      const Eigen::Vector3d x = world.objects().object_state(id).value.pose.orientation * Eigen::Vector3d::UnitX();
      EXPECT_NEAR(std::atan2(x.y(), x.x()) * 180 / M_PI, 45, 0.5);
      break;
    }
    case Kind::PortableComposite: {
      // Lay the can on its side (raised so it does not start in the floor): it rests on it.
      ASSERT_TRUE(world.edit().set_pose(id, {kFreeSpot + Eigen::Vector3d(0, 0, 0.1),
                                      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()))})
                      .ok());
      EXPECT_NEAR(settled_z(world, id), 0.033, 0.003);
      break;
    }
    case Kind::FixedBasic:
      // The post lies down along y: a ball dropped 15 cm off its old axis lands on it.
      ASSERT_TRUE(world.edit().set_orientation(id, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()))).ok());
      EXPECT_GT(drop_ball_at(0.0, -0.3 + 0.15), 0.2);
      break;
    case Kind::FixedComposite:
      // Turned by 90 degrees the 0.6 m side of the top runs along y.
      ASSERT_TRUE(world.edit().set_orientation(id, yaw(90)).ok());
      EXPECT_NEAR(drop_ball_at(2.4, 1.2 + 0.25), 0.44, 0.003);
      break;
    case Kind::Ramp: {
      ASSERT_TRUE(world.edit().set_orientation(id, yaw(180)).ok());  // now rises towards -x
      const double mid = world.objects().object(id)->ramp->depth() / 2;
      EXPECT_TRUE(occupied({2.0 - mid, -1.0, 0.03}));
      EXPECT_FALSE(occupied({2.0 + mid, -1.0, 0.03}));
      break;
    }
    case Kind::Door:
      EXPECT_EQ(world.edit().set_orientation(id, yaw(90)).code, ErrorCode::NotApplicable);
      break;
  }
}

TEST_P(Table1, ChangeColorAndTexture) {
  const ObjectId id = subject();
  const Color green{0.1f, 0.9f, 0.2f, 1.0f};
  ASSERT_TRUE(world.edit().set_color(id, green).ok());
  for (const auto& c : world.objects().object(id)->components) EXPECT_EQ(c.color, green);
  const std::string wood = source("worlds/DemoEnvironment_v1/textures/wood.bmp");
  ASSERT_TRUE(world.edit().set_texture(id, wood, 0).ok());
  const auto texture = world.objects().object_texture(id, 0).value;
  EXPECT_GT(texture.first, 0);
  EXPECT_EQ(texture.second, std::filesystem::path(wood).lexically_normal().string());
  // Not a 2^n BMP: refused, nothing changed.
  const auto dir = temp_dir("bad-texture");
  write_file(dir / "fake.bmp", "not an image");
  const Status bad = world.edit().set_texture(id, (dir / "fake.bmp").string(), 0);
  EXPECT_EQ(bad.code, ErrorCode::BadTexture);
  EXPECT_EQ(world.objects().object_texture(id, 0).value.second, texture.second);
  EXPECT_EQ(world.edit().set_color(id, {2.0f, 0, 0, 1}).code, ErrorCode::InvalidArgument);
}

TEST_P(Table1, ChangeMassAndDensity) {
  const ObjectId id = subject();
  const uint64_t before = world.state_hash();
  switch (kind()) {
    case Kind::PortableBasic:
      ASSERT_TRUE(world.edit().set_mass(id, 0.5).ok());
      EXPECT_NEAR(world.objects().object(id)->density, 0.5 / 0.001, 1e-9);  // density follows
      EXPECT_NEAR(mass_by_impulse(id), 0.5, 1e-9);
      break;
    case Kind::PortableComposite: {
      const double volume = world.objects().object(id)->volume();
      ASSERT_TRUE(world.edit().set_density(id, 1000).ok());
      EXPECT_NEAR(world.objects().object_mass(id).value, 1000 * volume, 1e-12);  // mass follows
      EXPECT_NEAR(mass_by_impulse(id), 1000 * volume, 1e-9);
      break;
    }
    case Kind::FixedBasic:
    case Kind::FixedComposite:
    case Kind::Ramp:
      expect_not_applicable(world.edit().set_mass(id, 1.0), before);
      expect_not_applicable(world.edit().set_density(id, 1.0), before);
      break;
    case Kind::Door:
      ASSERT_TRUE(world.edit().set_mass(id, 4.0).ok());  // the leaf is a body: it can be heavier
      EXPECT_NEAR(world.objects().object_mass(id).value, 4.0, 1e-12);
      ASSERT_TRUE(world.doors().set_switch_triggered(0, true).ok());
      run_for(world, 4.0);
      EXPECT_EQ(world.doors().door_state(0).value.gap, DoorGap::Open);
      break;
  }
}

TEST_P(Table1, SetVelocity) {
  const ObjectId id = subject();
  const uint64_t before = world.state_hash();
  if (!portable()) {
    expect_not_applicable(world.edit().set_linear_velocity(id, {1, 0, 0}), before);
    expect_not_applicable(world.edit().set_angular_velocity(id, {0, 0, 1}), before);
    return;
  }
  ASSERT_TRUE(world.edit().set_position(id, kFreeSpot + Eigen::Vector3d(0, 0, 1.0)).ok());
  ASSERT_TRUE(world.edit().set_linear_velocity(id, {0.5, 0, 2.0}).ok());
  ASSERT_TRUE(world.edit().set_angular_velocity(id, {0, 0, 3.0}).ok());
  run_for(world, 0.1);
  const ObjectState s = world.objects().object_state(id).value;
  EXPECT_NEAR(s.pose.position.x(), kFreeSpot.x() + 0.05, 1e-3);
  EXPECT_NEAR(s.pose.position.z(), 1.0 + 2.0 * 0.1 - 9.81 * 0.01 / 2, 2e-3);  // ballistic
  EXPECT_NEAR(s.angular_velocity.z(), 3.0, 1e-6);
}

TEST_P(Table1, SetForceAndTorque) {
  const ObjectId id = subject();
  const uint64_t before = world.state_hash();
  if (!portable()) {
    expect_not_applicable(world.edit().add_force(id, {10, 0, 0}), before);
    expect_not_applicable(world.edit().add_torque(id, {0, 0, 1}), before);
    return;
  }
  ASSERT_TRUE(world.edit().set_position(id, kFreeSpot + Eigen::Vector3d(0, 0, 1.0)).ok());
  const double mass = world.objects().object_mass(id).value;
  const Eigen::Matrix3d inertia = world.objects().object_inertia(id).value;
  ASSERT_TRUE(world.edit().add_force(id, {10, 0, 0}).ok());
  ASSERT_TRUE(world.edit().add_torque(id, {0, 0, 0.01}).ok());
  EXPECT_NEAR(world.objects().object_wrench(id).value.first.x(), 10, 1e-12);
  world.step();
  const ObjectState s = world.objects().object_state(id).value;
  EXPECT_NEAR(s.linear_velocity.x(), 10 * 0.001 / mass, 1e-9);
  EXPECT_NEAR(s.angular_velocity.z(), (inertia.inverse() * Eigen::Vector3d(0, 0, 0.01)).z() * 0.001, 1e-6);
  EXPECT_EQ(world.objects().object_wrench(id).value.first, Eigen::Vector3d::Zero());  // one step only
}

TEST_P(Table1, ChangeMagnetizable) {
  const ObjectId id = subject();
  const bool was = world.objects().object(id)->magnetizable;
  ASSERT_TRUE(world.edit().set_magnetizable(id, !was).ok());
  EXPECT_EQ(world.objects().object(id)->magnetizable, !was);
  const WorldSnapshot snap = world.snapshot();
  ASSERT_TRUE(world.edit().set_magnetizable(id, was).ok());
  ASSERT_TRUE(world.restore(snap).ok());
  EXPECT_EQ(world.objects().object(id)->magnetizable, !was);  // part of the restorable state
}

INSTANTIATE_TEST_SUITE_P(SeedTable1, Table1,
                         ::testing::Values(Kind::PortableBasic, Kind::PortableComposite,
                                           Kind::FixedBasic, Kind::FixedComposite, Kind::Ramp,
                                           Kind::Door),
                         kind_name);

}  // namespace
}  // namespace macsim::test
