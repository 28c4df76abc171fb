// The simulation_interfaces requests on the world, without DDS: spawning this project's XML
// (one object, a group, bad resources), deleting groups, setting states that are refused as a
// whole, filters and reset scopes. Every refusal leaves the state hash unchanged.
#include "sim_interfaces/sim_interfaces_dispatch.h"

#include <gtest/gtest.h>

#include <limits>

#include "support/world_helpers.h"

namespace macsim::test {
namespace {

namespace sim = sim_interfaces;
namespace si = simulation_interfaces::msg::dds_;
namespace ss = simulation_interfaces::srv::dds_;
namespace rc = si::Result_Constants;
namespace sc = ss::SpawnEntity_Response_Constants;

const char* kTwoBoxes =
    "<ENVIRONMENT><OBJECT><ID>a</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE><DIMS>0.1,0.1,0.1</DIMS>"
    "<POS>0,0,0.05</POS></OBJECT><OBJECT><ID>b</ID><TYPE>FIXED</TYPE><SHAPE>SPHERE</SHAPE>"
    "<RADIUS>0.05</RADIUS><POS>0.3,0,0.05</POS></OBJECT></ENVIRONMENT>";

ss::SpawnEntity_Request_ spawn_request(const std::string& name, const std::string& xml, double x) {
  ss::SpawnEntity_Request_ q;
  q.name(name);
  q.resource_string(xml);
  q.initial_pose().pose().position().x(x);
  q.initial_pose().pose().orientation().w(1);
  return q;
}

std::vector<std::string> names(const World& world, const std::string& filter) {
  ss::GetEntities_Request_ q;
  q.filters().filter(filter);
  return sim::get_entities(q, world).entities();
}

TEST(SimInterfacesDispatch, AnEnvironmentOfSeveralObjectsSpawnsAsAGroupAndIsDeletedAsOne) {
  World world(shipped_world("small_room.xml"));
  const auto r = sim::spawn_entity(spawn_request("pair", kTwoBoxes, 1.0), world);
  ASSERT_EQ(r.result().result(), rc::RESULT_OK) << r.result().error_message();
  EXPECT_EQ(r.entity_name(), "pair");
  EXPECT_EQ(names(world, "^pair/"), (std::vector<std::string>{"pair/a", "pair/b"}));
  ss::GetEntityState_Request_ where;
  where.entity("pair/b");
  EXPECT_NEAR(sim::get_entity_state(where, world).state().pose().position().x(), 1.3, 1e-9);
  ss::GetEntityInfo_Request_ info;
  info.entity("pair/b");
  EXPECT_EQ(sim::get_entity_info(info, world).info().category().category(),
            si::EntityCategory_Constants::CATEGORY_STATIC_OBJECT);
  ss::DeleteEntity_Request_ del;
  del.entity("pair");
  EXPECT_EQ(sim::delete_entity(del, world).result().result(), rc::RESULT_OK);
  EXPECT_TRUE(names(world, "^pair").empty());
}

TEST(SimInterfacesDispatch, BadSpawnsSayWhyAndChangeNothing) {
  World world(shipped_world("small_room.xml"));
  const uint64_t hash = world.state_hash();
  const int objects = world.objects().object_count();
  auto code = [&](const ss::SpawnEntity_Request_& q) {
    return sim::spawn_entity(q, world).result().result();
  };
  EXPECT_EQ(code(spawn_request("x", "", 0)), sc::NO_RESOURCE);
  EXPECT_EQ(code(spawn_request("x", "<ENVIRONMENT><OBJECT>", 0)), sc::RESOURCE_PARSE_ERROR);
  EXPECT_EQ(code(spawn_request("bad name", kTwoBoxes, 0)), sc::NAME_INVALID);
  EXPECT_EQ(code(spawn_request("", kTwoBoxes, 0)), sc::NAME_INVALID);
  EXPECT_EQ(code(spawn_request("x", kTwoBoxes, std::numeric_limits<double>::infinity())),
            sc::INVALID_POSE);
  EXPECT_EQ(code(spawn_request("x", kTwoBoxes, 1e308)), sc::INVALID_POSE);
  auto sdf = spawn_request("x", "", 0);
  sdf.uri("model.sdf");
  EXPECT_EQ(code(sdf), sc::UNSUPPORTED_FORMAT);
  auto missing = spawn_request("x", "", 0);
  missing.uri("no/such/file.xml");
  EXPECT_EQ(code(missing), sc::RESOURCE_PARSE_ERROR);
  auto namespaced = spawn_request("x", kTwoBoxes, 0);
  namespaced.entity_namespace("/robot2");
  EXPECT_EQ(code(namespaced), sc::NAMESPACE_INVALID);
  EXPECT_EQ(world.state_hash(), hash);
  EXPECT_EQ(world.objects().object_count(), objects);
}

TEST(SimInterfacesDispatch, AStateIsSetWhollyOrNotAtAll) {
  World world(shipped_world("small_room.xml"));
  ASSERT_EQ(sim::spawn_entity(spawn_request("pair", kTwoBoxes, 1.0), world).result().result(),
            rc::RESULT_OK);
  const uint64_t hash = world.state_hash();
  ss::SetEntityState_Request_ q;
  q.entity("pair/b");  // fixed: a pose, but no twist
  q.state().pose().position().x(2.0);
  q.state().pose().position().z(0.05);
  q.state().pose().orientation().w(1);
  q.state().twist().angular().z(1.0);
  EXPECT_EQ(sim::set_entity_state(q, world).result().result(), rc::RESULT_OPERATION_FAILED);
  q.entity("pair/a");  // portable, but a twist beyond every bound
  q.state().twist().angular().z(1e9);
  EXPECT_EQ(sim::set_entity_state(q, world).result().result(), rc::RESULT_OPERATION_FAILED);
  q.state().twist().angular().z(0);
  q.state().pose().orientation().w(0);  // no rotation at all
  EXPECT_EQ(sim::set_entity_state(q, world).result().result(),
            ss::SetEntityState_Response_Constants::INVALID_POSE);
  q.entity("kurt");
  q.state().pose().orientation().w(1);
  EXPECT_EQ(sim::set_entity_state(q, world).result().result(), rc::RESULT_OPERATION_FAILED);
  EXPECT_EQ(world.state_hash(), hash);
  // in another entity's frame: 0.5 m ahead of pair/b
  q.entity("pair/a");
  q.state().header().frame_id("pair/b");
  q.state().pose().position().x(0.5);
  q.state().pose().position().z(0.0);
  ASSERT_EQ(sim::set_entity_state(q, world).result().result(), rc::RESULT_OK);
  ss::GetEntityState_Request_ where;
  where.entity("pair/a");
  EXPECT_NEAR(sim::get_entity_state(where, world).state().pose().position().x(), 1.8, 1e-9);
  // frozen: the pose may change, a twist is refused before anything moves
  ASSERT_TRUE(world.edit().set_frozen(*world.objects().find_object("pair/a"), true).ok());
  const uint64_t frozen = world.state_hash();
  q.state().pose().position().x(0.6);
  q.state().twist().linear().x(0.5);
  const auto refused = sim::set_entity_state(q, world);
  EXPECT_EQ(refused.result().result(), rc::RESULT_OPERATION_FAILED);
  EXPECT_NE(refused.result().error_message().find("frozen"), std::string::npos);
  EXPECT_EQ(world.state_hash(), frozen);
}

TEST(SimInterfacesDispatch, ResetScopesMapToTheWorldsResets) {
  World world(shipped_world("small_room.xml"));
  const uint64_t start = world.state_hash();
  ASSERT_EQ(sim::spawn_entity(spawn_request("pair", kTwoBoxes, 1.0), world).result().result(),
            rc::RESULT_OK);
  for (int i = 0; i < 20; ++i) world.step();
  ss::ResetSimulation_Request_ q;
  q.scope(ss::ResetSimulation_Request_Constants::SCOPE_STATE);
  ASSERT_EQ(sim::reset_simulation(q, world).result().result(), rc::RESULT_OK);
  EXPECT_EQ(world.steps(), 20u);  // time goes on
  EXPECT_FALSE(names(world, "^pair").empty());
  q.scope(ss::ResetSimulation_Request_Constants::SCOPE_SPAWNED);
  EXPECT_EQ(sim::reset_simulation(q, world).result().result(), rc::RESULT_FEATURE_UNSUPPORTED);
  q.scope(ss::ResetSimulation_Request_Constants::SCOPE_ALL);
  ASSERT_EQ(sim::reset_simulation(q, world).result().result(), rc::RESULT_OK);
  EXPECT_EQ(world.steps(), 0u);
  EXPECT_TRUE(names(world, "^pair").empty());
  EXPECT_EQ(world.state_hash(), start);
}

}  // namespace
}  // namespace macsim::test
