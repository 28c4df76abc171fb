// The supervisor's codec: wire types to sim_core's and back.
#include "supervisor/supervisor_codec.h"

#include <gtest/gtest.h>

#include <set>

#include "support/world_helpers.h"

namespace macsim::test {
namespace {

namespace mm = macsim_msgs::msg::dds_;

TEST(SupervisorCodec, PosesGoThereAndBackExactly) {
  const Pose p{{1.5, -2.25, 0.125}, Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5)};
  const Pose back = codec::pose_of(codec::pose_message(p));
  EXPECT_EQ(back.position, p.position);
  EXPECT_EQ(back.orientation.coeffs(), p.orientation.coeffs());
}

TEST(SupervisorCodec, AnObjectMessageCarriesTheWorldsView) {
  World world(shipped_world("DemoWorld_v1.xml"));
  const ObjectId id = id_of(world, "environment_02/ramp_00");
  const mm::Object_ o = codec::object_message(world, id);
  EXPECT_EQ(o.id(), id);
  EXPECT_EQ(o.name(), "environment_02/ramp_00");
  EXPECT_EQ(o.kind(), mm::KIND_RAMP);
  EXPECT_FALSE(o.portable());
  EXPECT_EQ(o.mass(), 0.0);
  EXPECT_EQ(o.ramp()[0], world.objects().object(id)->ramp->width);
  EXPECT_EQ(o.components().size(), 1u);
  EXPECT_EQ(o.components()[0].shape(), mm::SHAPE_BOX);
  EXPECT_TRUE(codec::object_message(world, 999999).name().empty());  // unknown: empty
}

TEST(SupervisorCodec, ARequestedObjectBecomesASpecOrAClearError) {
  mm::Object_ o;
  mm::Component_ c;
  c.shape(mm::SHAPE_CYLINDER);
  c.size({0.05, 0, 0.2});
  c.pose().orientation().w(1);
  o.components().push_back(c);
  o.portable(true);
  o.mass(0.5);
  std::string error;
  auto spec = codec::spec_of(o, error);
  ASSERT_TRUE(spec.has_value()) << error;
  EXPECT_EQ(spec->components[0].shape, Shape::Cylinder);
  EXPECT_NEAR(spec->mass(), 0.5, 1e-12);  // the mass sets the density
  o.components()[0].shape(-7);
  EXPECT_FALSE(codec::spec_of(o, error).has_value());
  EXPECT_NE(error.find("-7"), std::string::npos);
  o.components()[0].shape(mm::SHAPE_BOX);
  o.kind(mm::KIND_DOOR_LEAF);
  EXPECT_FALSE(codec::spec_of(o, error).has_value());
  EXPECT_NE(error.find("KIND_OBJECT"), std::string::npos);
  o.kind(mm::KIND_RAMP);
  o.ramp({1.0, 0.1, 0.2});
  spec = codec::spec_of(o, error);
  ASSERT_TRUE(spec && spec->ramp);
  EXPECT_EQ(spec->ramp->angle, 0.2);
}

TEST(SupervisorCodec, EveryEventHasItsOwnName) {
  std::set<std::string> names;
  for (auto type : {WorldEvent::Type::SwitchTriggered, WorldEvent::Type::SwitchReleased,
                    WorldEvent::Type::DoorOpened, WorldEvent::Type::DoorClosed,
                    WorldEvent::Type::Penetration, WorldEvent::Type::Instability,
                    WorldEvent::Type::ObjectAttached, WorldEvent::Type::ObjectReleased}) {
    names.insert(codec::event_name(type));
  }
  EXPECT_EQ(names.size(), 8u);
  EXPECT_EQ(names.count("?"), 0u);
}

}  // namespace
}  // namespace macsim::test
