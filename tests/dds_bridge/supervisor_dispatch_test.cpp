// The supervisor's dispatch without DDS: every operation code and every error code, with the
// typed requests the client library builds. Each operation acts on a fresh demo world and is
// checked against sim_core's own view; every error leaves the state hash unchanged.
#include "supervisor/supervisor_dispatch.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>

#include "macsim/client/supervisor_requests.h"
#include "macsim/dds/convert.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

namespace mm = macsim_msgs::msg::dds_;
namespace rq = client::supervisor;
using Reply = mm::SupervisorReply_;

/// A fresh demo world and its snapshot store.
struct Fixture {
  World world{shipped_world("DemoWorld_v1.xml")};
  SnapshotStore snapshots;
  Reply call(const mm::SupervisorRequest_& request) { return dispatch(request, world, snapshots); }
  ObjectId id(const std::string& name) { return id_of(world, name); }
  /// Calls and expects success.
  Reply ok(const mm::SupervisorRequest_& request) {
    const Reply r = call(request);
    EXPECT_EQ(r.code(), mm::ERR_OK) << r.message();
    return r;
  }
};

const std::string kBox = "environment_01/box_red_small";
const std::string kBall = "environment_01/ball_green";
const std::string kPost = "environment_01/post";
const std::string kRamp = "environment_02/ramp_00";

mm::Object_ sphere_at(double x, double y, double z, double radius) {
  mm::Object_ o;
  mm::Component_ c;
  c.shape(mm::SHAPE_SPHERE);
  c.size({radius, 0, 0});
  c.pose().orientation().w(1.0);
  c.color({0.5f, 0.5f, 0.5f, 1.0f});
  o.components().push_back(c);
  o.kind(mm::KIND_OBJECT);
  o.portable(true);
  o.name("spawned");
  o.pose().position().x(x);
  o.pose().position().y(y);
  o.pose().position().z(z);
  o.pose().orientation().w(1.0);
  o.density(100);
  return o;
}

struct OperationCase {
  int32_t op;
  const char* name;
  std::function<void(Fixture&)> check;
};

/// One case per operation code: it succeeds and does what it says.
std::vector<OperationCase> operation_cases() {
  return {
      {mm::OP_LIST_OBJECTS, "list",
       [](Fixture& f) {
         const Reply r = f.ok(rq::list_objects());
         EXPECT_EQ(r.count(), f.world.objects().object_count());
         ASSERT_EQ(r.object_ids().size(), static_cast<std::size_t>(f.world.objects().object_count()));
         EXPECT_EQ(r.object_ids()[3], *f.world.objects().object_at(3));
         EXPECT_EQ(r.names()[3], f.world.objects().object(*f.world.objects().object_at(3))->name);
       }},
      {mm::OP_FIND_OBJECT, "find",
       [](Fixture& f) {
         const Reply r = f.ok(rq::find_object(kBox));
         EXPECT_EQ(r.object_id(), f.id(kBox));
         EXPECT_EQ(r.index(), *f.world.objects().index_of(f.id(kBox)));
       }},
      {mm::OP_FIND_BY_USER_DATA, "find by user data",
       [](Fixture& f) {
         const Reply r = f.ok(rq::find_by_user_data("box"));
         EXPECT_EQ(r.object_ids(), f.world.objects().find_by_user_data("box"));
         EXPECT_EQ(r.count(), 3);
       }},
      {mm::OP_GET_OBJECT, "get",
       [](Fixture& f) {
         const Reply r = f.ok(rq::get_object(f.id(kBox)));
         EXPECT_EQ(r.object().name(), kBox);
         EXPECT_EQ(r.object().kind(), mm::KIND_OBJECT);
         EXPECT_NEAR(r.object().mass(), 0.1, 1e-12);  // 100 kg/m^3 * 1 L
         EXPECT_EQ(r.object().components()[0].shape(), mm::SHAPE_BOX);
         EXPECT_EQ(r.object_id(), f.id(kBox));
       }},
      {mm::OP_CREATE_OBJECT, "create",
       [](Fixture& f) {
         const int before = f.world.objects().object_count();
         const Reply r = f.ok(rq::create_object(sphere_at(0, -1.0, 0.5, 0.07)));
         EXPECT_EQ(f.world.objects().object_count(), before + 1);
         ASSERT_NE(f.world.objects().object(r.object_id()), nullptr);
         EXPECT_EQ(f.world.objects().object(r.object_id())->components[0].shape, Shape::Sphere);
         EXPECT_EQ(f.world.objects().object(r.object_id())->components[0].size.x(), 0.07);
       }},
      {mm::OP_IMPORT_ENVIRONMENT, "import",
       [](Fixture& f) {
         const int before = f.world.objects().object_count();
         const Reply r = f.ok(rq::import_environment(
             source("worlds/DemoEnvironment_v1/objects/blocks.xml"), "more", {0, -4, 0}));
         EXPECT_EQ(f.world.objects().object_count(), before + static_cast<int>(r.object_ids().size()));
         ASSERT_FALSE(r.object_ids().empty());
         EXPECT_EQ(f.world.objects().object(r.object_ids()[0])->name.rfind("more/", 0), 0u);
       }},
      {mm::OP_DESTROY_OBJECT, "destroy",
       [](Fixture& f) {
         const ObjectId box = f.id(kBox);
         f.ok(rq::destroy_object(box));
         EXPECT_EQ(f.world.objects().object(box), nullptr);
       }},
      {mm::OP_DESTROY_BY_USER_DATA, "destroy by user data",
       [](Fixture& f) {
         EXPECT_EQ(f.ok(rq::destroy_by_user_data("box")).count(), 3);
         EXPECT_TRUE(f.world.objects().find_by_user_data("box").empty());
       }},
      {mm::OP_DESTROY_ALL, "destroy all",
       [](Fixture& f) {
         const int all = f.world.objects().object_count();
         const int portable = f.ok(rq::destroy_all(mm::DESTROY_PORTABLE_OBJECTS)).count();
         EXPECT_GT(portable, 0);
         EXPECT_EQ(f.world.objects().object_count(), all - portable);
         for (ObjectId each : f.world.objects().object_ids()) EXPECT_FALSE(f.world.objects().object(each)->portable);
         EXPECT_EQ(f.ok(rq::destroy_all(mm::DESTROY_FIXED_OBJECTS)).count(), all - portable);
         f.ok(rq::create_object(sphere_at(0, -1.0, 0.5, 0.07)));
         EXPECT_EQ(f.ok(rq::destroy_all(mm::DESTROY_EVERY_OBJECT)).count(), 1);
         EXPECT_EQ(f.world.objects().object_count(), 0);
       }},
      {mm::OP_SET_POSE, "set pose",
       [](Fixture& f) {
         const double s = std::sin(M_PI / 8), c = std::cos(M_PI / 8);
         f.ok(rq::set_pose(f.id(kBox), {0.3, 0.0, 0.05}, {0, 0, s, c}));
         const Pose p = f.world.objects().object_state(f.id(kBox)).value.pose;
         EXPECT_TRUE(p.position.isApprox(Eigen::Vector3d(0.3, 0.0, 0.05), 1e-12));
         EXPECT_NEAR(std::abs(p.orientation.dot(Eigen::Quaterniond(c, 0, 0, s))), 1.0, 1e-12);
       }},
      {mm::OP_SET_POSITION, "set position",
       [](Fixture& f) {
         f.ok(rq::set_position(f.id(kBox), {0.3, 0.0, 0.05}));
         EXPECT_TRUE(f.world.objects().object_state(f.id(kBox))
                         .value.pose.position.isApprox(Eigen::Vector3d(0.3, 0.0, 0.05), 1e-12));
       }},
      {mm::OP_SET_ORIENTATION, "set orientation",
       [](Fixture& f) {
         f.ok(rq::set_orientation(f.id(kBall), {0, 0, 1, 0}));  // a half turn about z
         const Eigen::Quaterniond q = f.world.objects().object_state(f.id(kBall)).value.pose.orientation;
         EXPECT_NEAR(std::abs(q.z()), 1.0, 1e-12);
       }},
      {mm::OP_SET_BOX_SIZE, "set box size",
       [](Fixture& f) {
         f.ok(rq::set_box_size(f.id(kBox), 0, {0.2, 0.1, 0.1}, true));
         EXPECT_EQ(f.world.objects().object(f.id(kBox))->components[0].size, Eigen::Vector3d(0.2, 0.1, 0.1));
       }},
      {mm::OP_SET_CYLINDER_SIZE, "set cylinder size",
       [](Fixture& f) {
         const ObjectId post = f.id(kPost);
         f.ok(rq::set_cylinder_size(post, 0, 0.05, 0.3, true));
         EXPECT_EQ(f.world.objects().object(post)->components[0].size.x(), 0.05);
         EXPECT_EQ(f.world.objects().object(post)->components[0].size.z(), 0.3);
       }},
      {mm::OP_SET_SPHERE_SIZE, "set sphere size",
       [](Fixture& f) {
         f.ok(rq::set_sphere_size(f.id(kBall), 0, 0.1, true));
         EXPECT_EQ(f.world.objects().object(f.id(kBall))->components[0].size.x(), 0.1);
       }},
      {mm::OP_SET_RAMP, "set ramp",
       [](Fixture& f) {
         f.ok(rq::set_ramp(f.id(kRamp), 1.0, 0.1, 0.2, true));
         const auto& ramp = f.world.objects().object(f.id(kRamp))->ramp;
         ASSERT_TRUE(ramp.has_value());
         EXPECT_EQ(ramp->width, 1.0);
         EXPECT_EQ(ramp->height, 0.1);
         EXPECT_EQ(ramp->angle, 0.2);
       }},
      {mm::OP_SET_COLOR, "set colour",
       [](Fixture& f) {
         f.ok(rq::set_color(f.id(kBox), {0.1f, 0.2f, 0.3f, 1.0f}));
         EXPECT_EQ(f.world.objects().object(f.id(kBox))->components[0].color,
                   (Color{0.1f, 0.2f, 0.3f, 1.0f}));
       }},
      {mm::OP_SET_TEXTURE, "set texture",
       [](Fixture& f) {
         f.ok(
             rq::set_texture(f.id(kBox), source("worlds/DemoEnvironment_v1/textures/checker.bmp")));
         EXPECT_NE(f.world.objects().object(f.id(kBox))->components[0].texture.find("checker.bmp"),
                   std::string::npos);
       }},
      {mm::OP_SET_MASS, "set mass",
       [](Fixture& f) {
         f.ok(rq::set_mass(f.id(kBox), 0.5));
         EXPECT_NEAR(f.world.objects().object_mass(f.id(kBox)).value, 0.5, 1e-12);
       }},
      {mm::OP_SET_DENSITY, "set density",
       [](Fixture& f) {
         f.ok(rq::set_density(f.id(kBox), 200));
         EXPECT_NEAR(f.world.objects().object_mass(f.id(kBox)).value, 0.2, 1e-12);
       }},
      {mm::OP_SET_LINEAR_VELOCITY, "set linear velocity",
       [](Fixture& f) {
         f.ok(rq::set_linear_velocity(f.id(kBall), {0.1, 0.2, 0.3}));
         EXPECT_EQ(f.world.objects().object_state(f.id(kBall)).value.linear_velocity,
                   Eigen::Vector3d(0.1, 0.2, 0.3));
       }},
      {mm::OP_SET_ANGULAR_VELOCITY, "set angular velocity",
       [](Fixture& f) {
         f.ok(rq::set_angular_velocity(f.id(kBall), {0.0, 0.0, 2.0}));
         EXPECT_EQ(f.world.objects().object_state(f.id(kBall)).value.angular_velocity,
                   Eigen::Vector3d(0, 0, 2));
       }},
      {mm::OP_ADD_FORCE, "add force",
       [](Fixture& f) {
         f.ok(rq::add_force(f.id(kBall), {3, 0, 0}));
         EXPECT_EQ(f.world.objects().object_wrench(f.id(kBall)).value.first, Eigen::Vector3d(3, 0, 0));
       }},
      {mm::OP_ADD_TORQUE, "add torque",
       [](Fixture& f) {
         f.ok(rq::add_torque(f.id(kBall), {0, 0, 0.5}));
         EXPECT_EQ(f.world.objects().object_wrench(f.id(kBall)).value.second, Eigen::Vector3d(0, 0, 0.5));
       }},
      {mm::OP_SET_FROZEN, "set frozen",
       [](Fixture& f) {
         f.ok(rq::set_frozen(f.id(kBall), true));
         EXPECT_TRUE(f.world.objects().object(f.id(kBall))->frozen);
       }},
      {mm::OP_SET_MAGNETIZABLE, "set magnetizable",
       [](Fixture& f) {
         f.ok(rq::set_magnetizable(f.id(kBall), true));
         EXPECT_TRUE(f.world.objects().object(f.id(kBall))->magnetizable);
       }},
      {mm::OP_SET_USER_DATA, "set user data",
       [](Fixture& f) {
         f.ok(rq::set_user_data(f.id(kBall), "round"));
         EXPECT_EQ(f.world.objects().object(f.id(kBall))->user_data, "round");
       }},
      {mm::OP_SET_USER_LABELS, "set user labels",
       [](Fixture& f) {
         f.ok(rq::set_user_labels(f.id(kBall), 4, 7));
         EXPECT_EQ(f.world.objects().object(f.id(kBall))->user_color, 4);
         EXPECT_EQ(f.world.objects().object(f.id(kBall))->user_shape, 7);
       }},
      {mm::OP_DOOR_COUNT, "door count",
       [](Fixture& f) { EXPECT_EQ(f.ok(rq::door_count()).count(), f.world.doors().door_count()); }},
      {mm::OP_GET_DOOR, "get door",
       [](Fixture& f) {
         const Reply r = f.ok(rq::get_door(0));
         EXPECT_EQ(r.door().name(), f.world.doors().door_name(0));
         EXPECT_EQ(r.door().gap(), mm::GAP_CLOSED);
         const DoorParts parts = f.world.doors().door_parts(0).value;
         EXPECT_EQ(r.object_ids(),
                   (std::vector<uint32_t>{parts.leaf, parts.frame, *parts.platform, *parts.base}));
       }},
      {mm::OP_GET_DOOR_BY_NAME, "get door by name",
       [](Fixture& f) {
         const int last = f.world.doors().door_count() - 1;
         const Reply r = f.ok(rq::get_door_by_name(f.world.doors().door_name(last)));
         EXPECT_EQ(r.index(), last);
         EXPECT_EQ(r.door().name(), f.world.doors().door_name(last));
         const DoorParts parts = f.world.doors().door_parts(last).value;
         EXPECT_EQ(r.object_ids(),
                   (std::vector<uint32_t>{parts.leaf, parts.frame, *parts.platform, *parts.base}));
       }},
      {mm::OP_SET_SWITCH_TRIGGERED, "trigger switch",
       [](Fixture& f) {
         f.ok(rq::set_switch_triggered(0, true));
         EXPECT_TRUE(f.world.doors().door_state(0).value.virtually_triggered);
       }},
      {mm::OP_SET_DOOR_POSITION, "move door",
       [](Fixture& f) {
         const ObjectId leaf = f.world.doors().door_parts(0).value.leaf;
         const Eigen::Vector3d to =
             f.world.objects().object_state(leaf).value.pose.position + Eigen::Vector3d(0, 0.5, 0);
         f.ok(rq::set_door_position(0, {to.x(), to.y(), to.z()}));
         EXPECT_TRUE(f.world.objects().object_state(leaf).value.pose.position.isApprox(to, 1e-9));
       }},
      {mm::OP_SET_SWITCH_POSITION, "move switch",
       [](Fixture& f) {
         const ObjectId platform = *f.world.doors().door_parts(0).value.platform;
         const Eigen::Vector3d to =
             f.world.objects().object_state(platform).value.pose.position + Eigen::Vector3d(0.3, 0, 0);
         f.ok(rq::set_switch_position(0, {to.x(), to.y(), to.z()}));
         EXPECT_TRUE(f.world.objects().object_state(platform).value.pose.position.isApprox(to, 1e-9));
       }},
      {mm::OP_RESET, "reset",
       [](Fixture& f) {
         const uint64_t loaded = f.world.state_hash();
         run_for(f.world, 0.1);
         f.ok(rq::reset(mm::RESET_POSES_AND_TIME));
         EXPECT_EQ(f.world.time(), 0.0);
         EXPECT_EQ(f.world.state_hash(), loaded);
         f.ok(rq::create_object(sphere_at(0, -1.0, 0.5, 0.07)));
         f.ok(rq::reset(mm::RESET_POSES));
         EXPECT_EQ(f.world.objects().object_count(), 25);  // spawned objects stay
         f.ok(rq::reset(mm::RESET_EVERYTHING));
         EXPECT_EQ(f.world.state_hash(), loaded);
       }},
      {mm::OP_SAVE_SNAPSHOT, "save snapshot",
       [](Fixture& f) {
         f.ok(rq::save_snapshot("start"));
         ASSERT_NE(f.snapshots.find("start"), nullptr);
         EXPECT_EQ(f.snapshots.find("start")->bytes, f.world.snapshot().bytes);
       }},
      {mm::OP_RESTORE_SNAPSHOT, "restore snapshot",
       [](Fixture& f) {
         f.ok(rq::save_snapshot("start"));
         const uint64_t saved = f.world.state_hash();
         run_for(f.world, 0.1);
         f.ok(rq::destroy_object(f.id(kBox)));
         f.ok(rq::restore_snapshot("start"));
         EXPECT_EQ(f.world.state_hash(), saved);
       }},
      {mm::OP_DELETE_SNAPSHOT, "delete snapshot",
       [](Fixture& f) {
         f.ok(rq::save_snapshot("a"));
         f.ok(rq::save_snapshot("b"));
         f.ok(rq::delete_snapshot("a"));
         EXPECT_EQ(f.snapshots.find("a"), nullptr);
         EXPECT_NE(f.snapshots.find("b"), nullptr);
         EXPECT_EQ(f.call(rq::restore_snapshot("a")).code(), mm::ERR_INVALID_ARGUMENT);
       }},
      {mm::OP_LIST_SNAPSHOTS, "list snapshots",
       [](Fixture& f) {
         EXPECT_TRUE(f.ok(rq::list_snapshots()).names().empty());
         f.ok(rq::save_snapshot("b"));
         f.ok(rq::save_snapshot("a"));
         const Reply r = f.ok(rq::list_snapshots());
         EXPECT_EQ(r.names(), (std::vector<std::string>{"a", "b"}));
         EXPECT_EQ(r.count(), 2);
       }},
      {mm::OP_STATE_HASH, "state hash",
       [](Fixture& f) { EXPECT_EQ(f.ok(rq::state_hash()).hash(), f.world.state_hash()); }},
  };
}

class Operation : public testing::TestWithParam<OperationCase> {};

TEST_P(Operation, SucceedsAndDoesWhatItSays) {
  Fixture f;
  GetParam().check(f);
}

/// A test name from a case's words.
std::string identifier(std::string words) {
  for (char& c : words) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return words;
}

INSTANTIATE_TEST_SUITE_P(EveryCode, Operation, testing::ValuesIn(operation_cases()),
                         [](const auto& param) { return identifier(param.param.name); });

struct ErrorCase {
  int32_t code;
  const char* what;
  std::function<mm::SupervisorRequest_(Fixture&)> request;
  const char* message_part;  ///< the reply's message names what was wrong
};

/// At least one request per error code; each changes nothing.
std::vector<ErrorCase> error_cases() {
  return {
      {mm::ERR_UNKNOWN_OBJECT, "unknown id",
       [](Fixture&) {
         return rq::set_position(999999, {0, 0, 1});
       },
       "999999"},
      {mm::ERR_UNKNOWN_OBJECT, "unknown name", [](Fixture&) { return rq::find_object("no/such"); },
       "no/such"},
      {mm::ERR_UNKNOWN_OBJECT, "unknown door", [](Fixture&) { return rq::get_door(7); }, "7"},
      {mm::ERR_UNKNOWN_OBJECT, "unknown door name",
       [](Fixture&) { return rq::get_door_by_name("doors/no_such_door"); }, "doors/no_such_door"},
      {mm::ERR_WRONG_GEOMETRY, "sphere size of a box",
       [](Fixture& f) { return rq::set_sphere_size(f.id(kBox), 0, 0.1); }, "box_red_small"},
      {mm::ERR_WRONG_GEOMETRY, "ramp of a box",
       [](Fixture& f) { return rq::set_ramp(f.id(kBox), 1, 0.1, 0.2); }, "not a ramp"},
      {mm::ERR_INVALID_ARGUMENT, "NaN position",
       [](Fixture& f) {
         return rq::set_position(f.id(kBox), {std::nan(""), 0, 1});
       },
       ""},
      {mm::ERR_INVALID_ARGUMENT, "negative size",
       [](Fixture& f) {
         return rq::set_box_size(f.id(kBox), 0, {0.1, -1, 0.1});
       },
       ""},
      {mm::ERR_INVALID_ARGUMENT, "unknown shape code",
       [](Fixture&) {
         mm::Object_ o = sphere_at(0, -1, 0.5, 0.1);
         o.components()[0].shape(99);
         return rq::create_object(o);
       },
       "99"},
      {mm::ERR_INVALID_ARGUMENT, "unknown destroy selection",
       [](Fixture&) { return rq::destroy_all(7); }, "7"},
      {mm::ERR_INVALID_ARGUMENT, "unknown reset scope", [](Fixture&) { return rq::reset(-1); },
       "-1"},
      {mm::ERR_INVALID_ARGUMENT, "unknown snapshot",
       [](Fixture&) { return rq::restore_snapshot("nope"); }, "nope"},
      {mm::ERR_NOT_APPLICABLE, "mass of a fixed object",
       [](Fixture& f) { return rq::set_mass(f.id(kPost), 1.0); }, "fixed"},
      {mm::ERR_NOT_APPLICABLE, "velocity of a fixed object",
       [](Fixture& f) {
         return rq::set_linear_velocity(f.id(kPost), {1, 0, 0});
       },
       "fixed"},
      {mm::ERR_PENETRATION, "into the post",
       [](Fixture& f) {
         const Eigen::Vector3d post = f.world.objects().object_state(f.id(kPost)).value.pose.position;
         return rq::set_position(f.id(kBox), {post.x(), post.y(), 0.1});
       },
       "post"},
      {mm::ERR_BAD_TEXTURE, "missing texture",
       [](Fixture& f) { return rq::set_texture(f.id(kBox), "/nonexistent/picture.bmp"); },
       "picture.bmp"},
      {mm::ERR_BAD_FILE, "missing environment",
       [](Fixture&) {
         return rq::import_environment("/nonexistent/env.xml", "x", {0, 0, 0});
       },
       "env.xml"},
      {mm::ERR_INVALID_ARGUMENT, "delete of an unknown snapshot",
       [](Fixture&) { return rq::delete_snapshot("nope"); }, "nope"},
      {mm::ERR_LIMIT_REACHED, "one snapshot more than the cap",
       [](Fixture& f) {
         f.snapshots.set_limits({2, SnapshotLimits{}.max_bytes});
         f.ok(rq::save_snapshot("a"));
         f.ok(rq::save_snapshot("b"));
         return rq::save_snapshot("c");
       },
       "--max-snapshots"},
      {mm::ERR_LIMIT_REACHED, "a snapshot over the byte cap",
       [](Fixture& f) {
         f.snapshots.set_limits({256, 1000});
         return rq::save_snapshot("big");
       },
       "--max-snapshot-bytes"},
      {mm::ERR_UNKNOWN_OPERATION, "unknown operation",
       [](Fixture&) {
         auto r = rq::list_objects();
         r.operation()._d() = 12345;
         return r;
       },
       "12345"},
  };
}

class Error : public testing::TestWithParam<ErrorCase> {};

TEST_P(Error, IsReportedWithItsCodeAndChangesNothing) {
  Fixture f;
  const uint64_t hash = f.world.state_hash();
  auto request = GetParam().request(f);
  request.client_id("tester");
  request.sequence_number(41);
  const Reply r = f.call(request);
  EXPECT_EQ(r.code(), GetParam().code) << r.message();
  EXPECT_NE(r.message().find(GetParam().message_part), std::string::npos) << r.message();
  EXPECT_FALSE(r.message().empty());
  EXPECT_EQ(r.client_id(), "tester");
  EXPECT_EQ(r.sequence_number(), 41u);
  EXPECT_EQ(f.world.state_hash(), hash);
}

INSTANTIATE_TEST_SUITE_P(EveryCode, Error, testing::ValuesIn(error_cases()),
                         [](const auto& param) { return identifier(param.param.what); });

/// Every `const int32 PREFIX... = N;` of the IDL.
std::set<int32_t> idl_codes(const std::string& prefix) {
  std::ifstream in(source("idl/kurt/macsim_msgs.idl"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  std::set<int32_t> codes;
  const std::regex line("const int32 " + prefix + "[A-Z_]+ = ([0-9]+);");
  for (auto m = std::sregex_iterator(all.begin(), all.end(), line); m != std::sregex_iterator();
       ++m) {
    codes.insert(std::stoi((*m)[1]));
  }
  return codes;
}

TEST(SupervisorDispatch, EveryOperationAndErrorCodeOfTheIdlHasItsTest) {
  // ERR_IN_PROGRESS is no answer of a dispatch: the servers' progress replies say it while a
  // request waits (tests/integration/busy_simulator_test.cpp). ERR_COMMANDS_MISSING answers a
  // step request only (sim_core's runner refuses it: runner_test.cpp,
  // integration/commands_sent_test.cpp).
  std::set<int32_t> operations, errors{mm::ERR_OK, mm::ERR_IN_PROGRESS, mm::ERR_COMMANDS_MISSING};
  for (const auto& c : operation_cases()) operations.insert(c.op);
  for (const auto& c : error_cases()) errors.insert(c.code);
  EXPECT_EQ(operations, idl_codes("OP_"));
  EXPECT_EQ(operations.size(), 40u);
  EXPECT_EQ(errors, idl_codes("ERR_"));
}

TEST(SupervisorDispatch, AComponentsQuaternionIsNormalizedBeforeItReachesOde) {
  Fixture f;
  mm::Object_ o = sphere_at(0, -1.0, 0.5, 0.07);
  o.components()[0].shape(mm::SHAPE_BOX);
  o.components()[0].size({0.1, 0.1, 0.1});
  o.components()[0].pose().orientation(dds::quaternion(0.7071, 0, 0, 0));  // not unit length
  const Reply r = f.ok(rq::create_object(o));
  const Eigen::Quaterniond q = f.world.objects().object(r.object_id())->components[0].pose.orientation;
  EXPECT_NEAR(q.norm(), 1.0, 1e-12);
  run_for(f.world, 0.2);
  EXPECT_TRUE(f.world.objects().object_state(r.object_id()).value.pose.position.allFinite());
  EXPECT_NEAR(f.world.objects().object_mass(r.object_id()).value, 0.1, 1e-9);
}

TEST(SupervisorDispatch, PenetrationWhenAllowedIsAppliedAndReported) {
  Fixture f;
  const Eigen::Vector3d post = f.world.objects().object_state(f.id(kPost)).value.pose.position;
  const Reply r = f.call(rq::set_position(f.id(kBox), {post.x(), post.y(), 0.1}, true));
  EXPECT_EQ(r.code(), mm::ERR_OK) << r.message();
  ASSERT_EQ(r.names().size(), 1u);
  EXPECT_EQ(r.names()[0], kPost);
}

TEST(SupervisorDispatch, ASnapshotOfAnotherWorldIsRefused) {
  Fixture demo;
  World small(shipped_world("small_room.xml"));
  ASSERT_TRUE(demo.snapshots.save("small", small.snapshot()).ok());
  const uint64_t hash = demo.world.state_hash();
  const Reply r = demo.call(rq::restore_snapshot("small"));
  EXPECT_EQ(r.code(), mm::ERR_INVALID_ARGUMENT);
  EXPECT_NE(r.message().find("fingerprint"), std::string::npos) << r.message();
  EXPECT_EQ(demo.world.state_hash(), hash);
}

TEST(SupervisorDispatch, AFullSnapshotStoreReplacesByNameAndADeleteFreesAPlace) {
  Fixture f;
  f.snapshots.set_limits({2, SnapshotLimits{}.max_bytes});
  f.ok(rq::save_snapshot("a"));
  f.ok(rq::save_snapshot("b"));
  const Reply full = f.call(rq::save_snapshot("c"));
  EXPECT_EQ(full.code(), mm::ERR_LIMIT_REACHED);
  EXPECT_NE(full.message().find("2"), std::string::npos) << full.message();
  EXPECT_NE(full.message().find("delete"), std::string::npos) << full.message();
  EXPECT_EQ(f.snapshots.find("c"), nullptr);
  run_for(f.world, 0.05);
  const uint64_t later = f.world.state_hash();
  f.ok(rq::save_snapshot("b"));  // replaced while full
  f.ok(rq::delete_snapshot("a"));
  f.ok(rq::save_snapshot("c"));
  EXPECT_EQ(f.ok(rq::list_snapshots()).names(), (std::vector<std::string>{"b", "c"}));
  run_for(f.world, 0.05);
  f.ok(rq::restore_snapshot("b"));
  EXPECT_EQ(f.world.state_hash(), later);
}

TEST(SupervisorDispatch, NamesEveryOperationAsItsBuilderIsNamed) {
  EXPECT_EQ(operation_name(mm::OP_SET_DENSITY), "set_density");
  EXPECT_EQ(operation_name(mm::OP_GET_DOOR_BY_NAME), "get_door_by_name");
  EXPECT_EQ(operation_name(mm::OP_LIST_SNAPSHOTS), "list_snapshots");
  EXPECT_EQ(operation_name(999), "operation_999");
}

}  // namespace
}  // namespace macsim::test
