// Supervisor operations beyond Table 1: ids and indices, composite mass and inertia against
// hand computation, penetration checks, bad requests, instability containment.
#include <gtest/gtest.h>


#include "macsim/images/image_files.h"
#include "macsim/sim_core/world_bounds.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

class WorldObjects : public ::testing::Test {
 protected:
  World world{shipped_world("DemoWorld_v1.xml")};
};

TEST_F(WorldObjects, IdsStayStableWhileIndicesShift) {
  const ObjectId first = *world.objects().object_at(0);
  const ObjectId second = *world.objects().object_at(1);
  const ObjectId third = *world.objects().object_at(2);
  ASSERT_TRUE(world.edit().destroy_object(second).ok());
  EXPECT_EQ(world.objects().object_at(0), first);
  EXPECT_EQ(world.objects().object_at(1), third);  // the seed's warning: indices shift
  EXPECT_EQ(world.objects().index_of(third), 1);
  EXPECT_FALSE(world.objects().index_of(second).has_value());
  auto created = world.edit().create_object(primitive(Shape::Sphere, {0.05, 0, 0}, {-0.5, 0.3, 0.5}));
  ASSERT_TRUE(created.ok());
  EXPECT_GT(created.value, third);  // ids are never reused
}

TEST_F(WorldObjects, CreatingAndImportingStopAtTheCapOnObjects) {
  EXPECT_EQ(world.edit().max_objects(), bounds::kMaxObjects);
  const auto count = static_cast<std::size_t>(world.objects().object_count());
  world.edit().set_max_objects(count + 1);
  ASSERT_TRUE(world.edit().create_object(primitive(Shape::Sphere, {0.05, 0, 0}, {-0.5, 0.3, 0.5})).ok());
  const uint64_t hash = world.state_hash();
  const auto refused =
      world.edit().create_object(primitive(Shape::Sphere, {0.05, 0, 0}, {-0.5, -0.3, 0.5}));
  EXPECT_EQ(refused.status.code, ErrorCode::LimitReached);
  EXPECT_NE(refused.status.message.find("--max-objects"), std::string::npos)
      << refused.status.message;
  EXPECT_NE(refused.status.message.find(std::to_string(count + 1)), std::string::npos);
  const auto imported = world.edit().import_environment(
      source("worlds/DemoEnvironment_v1/objects/blocks.xml"), "more", Pose{});
  EXPECT_EQ(imported.status.code, ErrorCode::LimitReached) << imported.status.message;
  EXPECT_EQ(world.state_hash(), hash);  // nothing changed
  ASSERT_TRUE(world.edit().destroy_object(*world.objects().object_at(0)).ok());  // a place freed
  EXPECT_TRUE(world.edit().create_object(primitive(Shape::Sphere, {0.05, 0, 0}, {-0.5, -0.3, 0.5})).ok());
}

TEST_F(WorldObjects, LooksUpByUserDataAndDestroysGroups) {
  const auto cans = world.objects().find_by_user_data("can");
  EXPECT_EQ(cans.size(), 5u);
  EXPECT_EQ(world.objects().find_by_user_data("nothing").size(), 0u);
  const int before = world.objects().object_count();
  EXPECT_EQ(world.edit().destroy_objects("can"), 5);
  EXPECT_EQ(world.objects().object_count(), before - 5);
  EXPECT_EQ(world.objects().find_by_user_data("can").size(), 0u);
}

TEST_F(WorldObjects, DestroysAllPortableOrAllFixedObjects) {
  const int portable = world.edit().destroy_all_portable_objects();
  EXPECT_GT(portable, 0);
  for (ObjectId id : world.objects().object_ids()) EXPECT_FALSE(world.objects().object(id)->portable);
  EXPECT_EQ(world.doors().door_count(), 0);  // its leaf and platform were portable: the doors went too
  const int fixed = world.edit().destroy_all_fixed_objects();
  EXPECT_GT(fixed, 0);
  EXPECT_EQ(world.objects().object_count(), 0);
  run_for(world, 0.1);  // an empty world still steps
}

TEST_F(WorldObjects, CompositeMassAndInertiaMatchHandComputation) {
  // The bubble-top can: cylinder (r 0.033, h 0.115, centre z 0.0575) + sphere (r 0.02, z 0.115).
  const ObjectId can = id_of(world, "environment_00/can_00");
  const double rho = world.objects().object(can)->density;
  const double r = 0.033, h = 0.115, rs = 0.02;
  const double mc = rho * M_PI * r * r * h, ms = rho * 4.0 / 3 * M_PI * rs * rs * rs;
  const double m = mc + ms;
  const double zc = 0.0575, zs = 0.115, com = (mc * zc + ms * zs) / m;
  const double ixx = mc * (3 * r * r + h * h) / 12 + mc * (zc - com) * (zc - com) +
                     0.4 * ms * rs * rs + ms * (zs - com) * (zs - com);
  const double izz = mc * r * r / 2 + 0.4 * ms * rs * rs;
  EXPECT_NEAR(world.objects().object_mass(can).value, m, 1e-15);
  EXPECT_NEAR(world.objects().object_center_of_mass(can).value.z(), com, 1e-12);
  const Eigen::Matrix3d inertia = world.objects().object_inertia(can).value;
  EXPECT_NEAR(inertia(0, 0), ixx, 1e-12);
  EXPECT_NEAR(inertia(1, 1), ixx, 1e-12);
  EXPECT_NEAR(inertia(2, 2), izz, 1e-12);
  EXPECT_NEAR(inertia(0, 1), 0.0, 1e-15);

  // Density and mass stay consistent both ways; inertia scales exactly.
  ASSERT_TRUE(world.edit().set_density(can, 2 * rho).ok());
  EXPECT_NEAR(world.objects().object_mass(can).value, 2 * m, 1e-15);
  EXPECT_NEAR(world.objects().object_inertia(can).value(0, 0), 2 * ixx, 1e-12);
  ASSERT_TRUE(world.edit().set_mass(can, 0.1).ok());
  EXPECT_NEAR(world.objects().object(can)->density, 0.1 / world.objects().object(can)->volume(), 1e-9);
  EXPECT_NEAR(world.objects().object_inertia(can).value(2, 2), izz * 0.1 / m, 1e-12);
}

TEST_F(WorldObjects, RelocatingIntoAnotherObjectIsRefusedByDefault) {
  const ObjectId box = id_of(world, "environment_01/box_red_small");
  const Eigen::Vector3d before = world.objects().object_state(box).value.pose.position;
  const uint64_t hash = world.state_hash();
  const Status s = world.edit().set_position(box, {0.0, -0.3, 0.2});  // inside the post
  EXPECT_EQ(s.code, ErrorCode::Penetration);
  EXPECT_NE(s.message.find("environment_01/post"), std::string::npos) << s.message;
  EXPECT_EQ(world.objects().object_state(box).value.pose.position, before);
  EXPECT_EQ(world.state_hash(), hash);
}

TEST_F(WorldObjects, CreatingInsideAnotherObjectCanBeRefusedAndChangesNothing) {
  // Found by the request fuzzer: the refusal read the new object's name after freeing it.
  const uint64_t hash = world.state_hash();
  const int count = world.objects().object_count();
  ObjectSpec spec = box_object({0.0, -0.3, 0.2}, {0.05, 0.05, 0.05});  // inside the post
  spec.name = "intruder";
  const auto made = world.edit().create_object(spec, PenetrationPolicy::Refuse);
  EXPECT_EQ(made.status.code, ErrorCode::Penetration);
  EXPECT_NE(made.status.message.find("'intruder' would penetrate environment_01/post"),
            std::string::npos)
      << made.status.message;
  EXPECT_EQ(world.objects().object_count(), count);
  EXPECT_EQ(world.state_hash(), hash);  // the next id too
}

TEST_F(WorldObjects, RelocatingIntoAnotherObjectCanBeAllowedAndIsReported) {
  const ObjectId box = id_of(world, "environment_01/box_red_small");
  const Status s = world.edit().set_position(box, {0.0, -0.3, 0.2}, PenetrationPolicy::Allow);
  ASSERT_TRUE(s.ok());
  EXPECT_EQ(s.penetrated, std::vector<std::string>{"environment_01/post"});
  bool reported = false;
  for (const auto& e : world.take_events()) reported |= e.type == WorldEvent::Type::Penetration;
  EXPECT_TRUE(reported);
  // The solver pushes it out gently (contacts correct at most 1 m/s; then it falls 0.15 m,
  // about 1.7 m/s): nothing explodes and nothing goes NaN.
  double fastest = 0;
  for (int i = 0; i < 2000; ++i) {
    world.step();
    fastest = std::max(fastest, world.objects().object_state(box).value.linear_velocity.norm());
  }
  EXPECT_TRUE(world.objects().object_state(box).value.pose.position.allFinite());
  EXPECT_LT(fastest, 3.0);
  for (const auto& e : world.take_events()) EXPECT_NE(e.type, WorldEvent::Type::Instability);
}

TEST_F(WorldObjects, GrowingIntoANeighbourIsRefused) {
  const ObjectId post = id_of(world, "environment_01/post");
  const Status s = world.edit().set_cylinder_size(post, 0, 2.0, 0.4);  // would swallow the robot
  EXPECT_EQ(s.code, ErrorCode::Penetration);
  EXPECT_NEAR(world.objects().object(post)->components[0].size.x(), 0.06, 1e-15);
}

TEST_F(WorldObjects, BadRequestsGiveClearErrorsAndLeaveTheWorldUnchanged) {
  const ObjectId box = id_of(world, "environment_01/box_red_small");
  const ObjectId can = id_of(world, "environment_00/can_00");
  const double nan = std::nan("");
  const uint64_t hash = world.state_hash();
  const int count = world.objects().object_count();
  struct Case {
    Status status;
    ErrorCode expected;
  };
  const std::vector<Case> cases = {
      {world.edit().set_position(999999, {0, 0, 1}), ErrorCode::UnknownObject},
      {world.edit().set_position(box, {nan, 0, 1}), ErrorCode::InvalidArgument},
      {world.edit().set_orientation(box, Eigen::Quaterniond(nan, 0, 0, 0)), ErrorCode::InvalidArgument},
      {world.edit().set_box_size(box, 0, {0.1, -0.1, 0.1}), ErrorCode::InvalidArgument},
      {world.edit().set_box_size(box, 0, {0.1, 0.0, 0.1}), ErrorCode::InvalidArgument},
      {world.edit().set_box_size(box, 0, {0.1, nan, 0.1}), ErrorCode::InvalidArgument},
      {world.edit().set_cylinder_size(box, 0, 0.1, 0.1), ErrorCode::WrongGeometry},
      {world.edit().set_sphere_size(can, 0, 0.1), ErrorCode::WrongGeometry},
      {world.edit().set_box_size(can, 7, {0.1, 0.1, 0.1}), ErrorCode::InvalidArgument},
      {world.edit().set_mass(box, -1.0), ErrorCode::InvalidArgument},
      {world.edit().set_mass(box, nan), ErrorCode::InvalidArgument},
      {world.edit().set_density(box, 0.0), ErrorCode::InvalidArgument},
      {world.edit().set_linear_velocity(box, {std::numeric_limits<double>::infinity(), 0, 0}),
       ErrorCode::InvalidArgument},
      {world.edit().add_force(box, {nan, 0, 0}), ErrorCode::InvalidArgument},
      {world.edit().set_ramp(box, {1, 0.1, 0.2}), ErrorCode::WrongGeometry},
      {world.edit().set_ramp(id_of(world, "environment_02/ramp_00"), {1, 0.1, 2.0}),
       ErrorCode::InvalidArgument},
      {world.edit().set_color(box, {std::nanf(""), 0, 0, 1}), ErrorCode::InvalidArgument},
      {world.edit().set_texture(box, "no/such.bmp"), ErrorCode::BadTexture},
      {world.doors().set_switch_triggered(5, true), ErrorCode::UnknownObject},
      {world.doors().set_door_position(0, {nan, 0, 0}), ErrorCode::InvalidArgument},
      {world.edit().create_object(primitive(Shape::Sphere, {-1, 0, 0}, {0, 0, 1})).status,
       ErrorCode::InvalidArgument},
      {world.edit().create_object(ObjectSpec{}).status, ErrorCode::InvalidArgument},
      {world.edit().import_environment("no/such/file.xml", "door_09", at(0, 0, 0)).status,
       ErrorCode::BadFile},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(cases[i].status.code, cases[i].expected)
        << "case " << i << ": " << cases[i].status.message;
    EXPECT_FALSE(cases[i].status.message.empty()) << "case " << i;
  }
  EXPECT_EQ(world.state_hash(), hash);
  EXPECT_EQ(world.objects().object_count(), count);
}

TEST_F(WorldObjects, TexturesMustBeSquarePowerOfTwoBmpsUpTo1024) {
  const ObjectId box = id_of(world, "environment_01/box_red_small");
  const auto dir = temp_dir("textures");
  auto write = [&](const std::string& name, int w, int h) {
    macsim::images::write_image((dir / name).string(), cv::Mat(h, w, CV_8UC3, cv::Scalar(10, 200, 30)));
    return (dir / name).string();
  };
  EXPECT_TRUE(world.edit().set_texture(box, write("ok_1024.bmp", 1024, 1024)).ok());
  EXPECT_TRUE(world.edit().set_texture(box, write("ok_1.bmp", 1, 1)).ok());
  for (const auto& bad : {write("npot.bmp", 100, 100), write("wide.bmp", 64, 32),
                          write("huge.bmp", 2048, 2048), write("png.png", 64, 64)}) {
    const Status s = world.edit().set_texture(box, bad);
    EXPECT_EQ(s.code, ErrorCode::BadTexture) << bad;
    EXPECT_NE(s.message.find(bad), std::string::npos) << s.message;
  }
  EXPECT_NE(world.objects().object(box)->components[0].texture.find("ok_1.bmp"), std::string::npos);
}

TEST_F(WorldObjects, FrozenObjectsStayPutButStillBlock) {
  const ObjectId ball = id_of(world, "environment_01/ball_green");
  ASSERT_TRUE(world.edit().set_position(ball, {-0.5, 0.3, 0.5}).ok());
  ASSERT_TRUE(world.edit().set_frozen(ball, true).ok());
  run_for(world, 1.0);
  EXPECT_NEAR(world.objects().object_state(ball).value.pose.position.z(), 0.5, 1e-9);  // no gravity
  auto box = world.edit().create_object(primitive(Shape::Box, {0.05, 0.05, 0.05}, {-0.5, 0.3, 0.8}));
  ASSERT_TRUE(box.ok());
  EXPECT_NEAR(settled_z(world, box.value, 1.0), 0.5 + 0.08 + 0.025, 0.003);  // rests on it
  EXPECT_EQ(world.edit().set_linear_velocity(ball, {1, 0, 0}).code, ErrorCode::NotApplicable);
  ASSERT_TRUE(world.edit().set_frozen(ball, false).ok());
  run_for(world, 1.5);
  EXPECT_LT(world.objects().object_state(ball).value.pose.position.z(), 0.2);  // falls again
}

TEST_F(WorldObjects, AnUnstableBodyIsPutBackAndReportedNotPropagated) {
  const ObjectId ball = id_of(world, "environment_01/ball_white");
  run_for(world, 0.5);
  const Eigen::Vector3d before = world.objects().object_state(ball).value.pose.position;
  // The largest force a request may apply, on a small ball: one step later the body is
  // implausible (beyond 1000 m/s).
  ASSERT_TRUE(world.edit().add_force(ball, {0, 0, bounds::kMaxForce}).ok());
  world.step();
  const ObjectState after = world.objects().object_state(ball).value;
  EXPECT_TRUE(after.pose.position.isApprox(before, 1e-6));
  EXPECT_EQ(after.linear_velocity, Eigen::Vector3d::Zero());
  bool reported = false;
  for (const auto& e : world.take_events()) {
    reported |= e.type == WorldEvent::Type::Instability && e.subject == "environment_01/ball_white";
  }
  EXPECT_TRUE(reported);
  run_for(world, 0.5);
  for (ObjectId id : world.objects().object_ids()) {
    EXPECT_TRUE(world.objects().object_state(id).value.pose.position.allFinite()) << world.objects().object(id)->name;
  }
}

TEST_F(WorldObjects, ObjectsWithoutTheNamingConventionAreReachableByName) {
  EXPECT_TRUE(world.objects().find_object("room/north").has_value());
  EXPECT_TRUE(world.objects().find_object("environment_02/ramp_00").has_value());
  EXPECT_FALSE(world.objects().find_object("ramp_00").has_value());  // names are full paths
}

}  // namespace
}  // namespace macsim::test
