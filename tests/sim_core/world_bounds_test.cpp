// One set of bounds for what a world file may hold, what a spec built in code may hold and what
// a supervisor request may set: huge or tiny magnitudes are refused with the element's file and
// line (or an InvalidArgument status) before they reach ODE, and nothing changes.
#include "macsim/sim_core/world_bounds.h"

#include <gtest/gtest.h>

#include "macsim/sim_core/world_loader.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

// Loading `body` (inside <WORLD>) fails at `line` naming `fragment`.
void expect_refused(const std::string& body, int line, const std::string& fragment) {
  SCOPED_TRACE(body);
  try {
    load_world_string("<WORLD>\n" + body + "\n</WORLD>", "bounds.xml");
    FAIL() << "loaded";
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.file(), "bounds.xml");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

const std::string kBox = "<OBJECT><ID>b</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE>";

TEST(WorldBounds, AWorldFileOutOfBoundsIsRefusedWithItsLine) {
  expect_refused(kBox + "<DIMS>1e308,1,1</DIMS></OBJECT>", 2, "box side");
  expect_refused(kBox + "<DIMS>1e-300,1,1</DIMS></OBJECT>", 2, "box side");
  expect_refused(kBox + "<DIMS>0.1,0.1,0.1</DIMS><POS>1e308,0,0</POS></OBJECT>", 2, "position");
  expect_refused(kBox + "<DIMS>0.1,0.1,0.1</DIMS><DENSITY>1e308</DENSITY></OBJECT>", 2, "density");
  expect_refused(kBox + "<DIMS>100,100,100</DIMS></OBJECT>", 2, "mass");  // 1e8 kg portable
  expect_refused(
      "<OBJECT><ID>s</ID><TYPE>PORTABLE</TYPE><SHAPE>SPHERE</SHAPE><RADIUS>1e308</RADIUS></OBJECT>",
      2, "radius");
  expect_refused("<PHYSICS><STEP>1e308</STEP></PHYSICS>", 2, "step");
  expect_refused("<PHYSICS><STEP>1e-300</STEP></PHYSICS>", 2, "step");
  expect_refused("<PHYSICS><GRAVITY>0,0,-1e308</GRAVITY></PHYSICS>", 2, "gravity");
  expect_refused("<PHYSICS><ERP>1e308</ERP></PHYSICS>", 2, "ERP");
  expect_refused("<PHYSICS><CFM>1e308</CFM></PHYSICS>", 2, "CFM");
  expect_refused("<PHYSICS>\n<ITERATIONS>0.5</ITERATIONS></PHYSICS>", 3, "whole number");
  expect_refused("<PHYSICS>\n<ITERATIONS>1e9</ITERATIONS></PHYSICS>", 3, "whole number");
  // A seed past 32 bits (found by the world loader's fuzzer), or with a fraction.
  expect_refused("<PHYSICS>\n<SEED>1.7e104</SEED></PHYSICS>", 3, "<SEED> must be a whole number");
  expect_refused("<PHYSICS>\n<SEED>4294967296</SEED></PHYSICS>", 3, "<SEED> must be a whole number");
  expect_refused("<PHYSICS>\n<SEED>0.5</SEED></PHYSICS>", 3, "<SEED> must be a whole number");
  expect_refused("<ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE><POS>1e308,0,0</POS></ROBOT>", 2,
                 "position");
  expect_refused("<RAMP><ID>r</ID><WIDTH>1</WIDTH><HEIGHT>0.1</HEIGHT><ANGLE>1e-10</ANGLE></RAMP>",
                 2, "ramp length");
}

TEST(WorldBounds, ASpecBuiltInCodeKeepsTheSameBounds) {
  WorldSpec spec = shipped_world("small_room.xml");
  spec.physics.step = 1e-300;
  EXPECT_THROW(World{spec}, WorldFileError);
  spec = shipped_world("small_room.xml");
  spec.objects.front().pose.position.x() = 1e308;
  EXPECT_THROW(World{spec}, WorldFileError);
  JointSpec same;
  same.body1 = same.body2 = "a";
  EXPECT_NE(bounds::joint_problem(same)->find("two different bodies"), std::string::npos);
  JointSpec huge;
  huge.body1 = "a";
  huge.axis = {1e308, 1e308, 0};
  EXPECT_TRUE(bounds::joint_problem(huge).has_value());
}

TEST(WorldBounds, NamesFollowOneRuleEverywhere) {
  EXPECT_FALSE(bounds::name_problem("doors/door_00/door_component/leaf").has_value());
  EXPECT_TRUE(bounds::name_problem("a//b").has_value());
  EXPECT_TRUE(bounds::name_problem("../x").has_value());
  EXPECT_TRUE(bounds::name_problem("a b").has_value());
  EXPECT_TRUE(bounds::name_problem(std::string(300, 'a')).has_value());
  EXPECT_TRUE(bounds::id_problem("a/b").has_value());  // one segment: an <ID>
  EXPECT_TRUE(bounds::id_problem("..").has_value());
  World world(shipped_world("DemoWorld_v1.xml"));
  ObjectSpec spec = box_object({0, -1.0, 0.3}, {0.1, 0.1, 0.1});
  spec.name = "a//b";
  EXPECT_EQ(world.edit().create_object(spec).status.code, ErrorCode::InvalidArgument);
  spec.name = "mine/box";
  EXPECT_TRUE(world.edit().create_object(spec).ok());
  EXPECT_EQ(
      world.edit().import_environment(source("worlds/DemoEnvironment_v1/objects/blocks.xml"), "..", Pose{})
          .status.code,
      ErrorCode::InvalidArgument);
}

TEST(WorldBounds, HostileRequestsAreRefusedAndChangeNothing) {
  World world(shipped_world("DemoWorld_v1.xml"));
  run_for(world, 0.1);
  const ObjectId box = id_of(world, "environment_01/box_red_small");
  const ObjectId ball = id_of(world, "environment_01/ball_green");
  const uint64_t hash = world.state_hash();
  const double huge = 1e308, tiny = 1e-300;
  std::vector<std::pair<const char*, Status>> refused{
      {"mass huge", world.edit().set_mass(box, huge)},
      {"mass tiny", world.edit().set_mass(box, tiny)},
      {"density huge", world.edit().set_density(box, huge)},
      {"box huge", world.edit().set_box_size(box, 0, {huge, 0.1, 0.1}, PenetrationPolicy::Allow)},
      {"box tiny", world.edit().set_box_size(box, 0, {tiny, 0.1, 0.1}, PenetrationPolicy::Allow)},
      {"sphere huge", world.edit().set_sphere_size(ball, 0, huge, PenetrationPolicy::Allow)},
      {"position far", world.edit().set_position(box, {huge, 0, 0}, PenetrationPolicy::Allow)},
      {"orientation zero", world.edit().set_orientation(box, Eigen::Quaterniond(0, 0, 0, 0))},
      {"orientation tiny", world.edit().set_orientation(box, Eigen::Quaterniond(tiny, 0, 0, 0))},
      {"velocity huge", world.edit().set_linear_velocity(ball, {huge, 0, 0})},
      {"spin huge", world.edit().set_angular_velocity(ball, {0, 0, 1e6})},
      {"force huge", world.edit().add_force(ball, {0, huge, 0})},
      {"torque huge", world.edit().add_torque(ball, {0, 0, huge})},
      {"switch far", world.doors().set_switch_position(0, {huge, 0, 0})},
      {"door far", world.doors().set_door_position(0, {0, huge, 0})},
      {"import far", world.edit()
                         .import_environment(source("worlds/DemoEnvironment_v1/objects/blocks.xml"),
                                             "far", Pose{{huge, 0, 0}, {1, 0, 0, 0}})
                         .status},
      {"create dense", world.edit()
                           .create_object([huge] {
                             ObjectSpec s = box_object({0, -1.0, 0.3}, {0.1, 0.1, 0.1});
                             s.density = huge;
                             return s;
                           }())
                           .status},
      {"create huge portable",
       world.edit().create_object(box_object({0, -1.0, 0.3}, {500, 500, 500})).status},
  };
  for (const auto& [what, status] : refused) {
    EXPECT_EQ(status.code, ErrorCode::InvalidArgument) << what << ": " << status.message;
    EXPECT_FALSE(status.message.empty()) << what;
  }
  EXPECT_EQ(world.state_hash(), hash);
  run_for(world, 0.1);  // and it steps on
  EXPECT_TRUE(world.objects().object_state(box).value.pose.position.allFinite());
}

TEST(WorldBounds, ImportsNestAndFanOutWithinLimits) {
  const auto dir = temp_dir("bounds_imports");
  // 40 files each importing the next: refused where the depth runs out, naming file and line.
  for (int i = 0; i < 40; ++i) {
    write_file(dir / ("deep_" + std::to_string(i) + ".xml"),
               "<ENVIRONMENT>\n<IMPORT><ID>n</ID><NAME>deep_" + std::to_string(i + 1) +
                   ".xml</NAME></IMPORT></ENVIRONMENT>");
  }
  write_file(dir / "deep_40.xml", "<ENVIRONMENT/>");
  write_file(dir / "deep.xml", "<WORLD><IMPORT><ID>n</ID><NAME>deep_0.xml</NAME></IMPORT></WORLD>");
  try {
    load_world_file((dir / "deep.xml").string());
    FAIL() << "loaded";
  } catch (const WorldFileError& e) {
    EXPECT_NE(std::string(e.what()).find("nest at most"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 2);
  }
  // 20 files each importing the next twice (2^20 imports): refused once the count runs out.
  for (int i = 0; i < 20; ++i) {
    const std::string next = "wide_" + std::to_string(i + 1) + ".xml";
    write_file(dir / ("wide_" + std::to_string(i) + ".xml"),
               "<ENVIRONMENT><IMPORT><ID>a</ID><NAME>" + next +
                   "</NAME></IMPORT><IMPORT><ID>b</ID><NAME>" + next +
                   "</NAME></IMPORT></ENVIRONMENT>");
  }
  write_file(dir / "wide_20.xml", "<ENVIRONMENT/>");
  write_file(dir / "wide.xml", "<WORLD><IMPORT><ID>w</ID><NAME>wide_0.xml</NAME></IMPORT></WORLD>");
  try {
    load_world_file((dir / "wide.xml").string());
    FAIL() << "loaded";
  } catch (const WorldFileError& e) {
    EXPECT_NE(std::string(e.what()).find("fan out"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(WorldBounds, TheLimitsAreOverridableAndFilesMayComeFromMemory) {
  MemoryFiles files;
  files.add("mem/world.xml",
            "<WORLD>\n<IMPORT><ID>a</ID><NAME>part.xml</NAME></IMPORT>\n"
            "<IMPORT><ID>b</ID><NAME>part.xml</NAME></IMPORT>\n</WORLD>");
  const std::string box_c = "<OBJECT><ID>c</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE>";
  files.add("mem/part.xml", "<ENVIRONMENT>\n" + kBox + "<DIMS>0.1,0.1,0.1</DIMS></OBJECT>\n" +
                                box_c + "<DIMS>0.1,0.1,0.1</DIMS></OBJECT>\n</ENVIRONMENT>");
  LoadOptions options;
  options.files = &files;
  EXPECT_EQ(load_world_file("mem/world.xml", options).objects.size(), 4u);  // from memory
  options.limits.max_objects = 3;
  try {
    load_world_file("mem/world.xml", options);
    FAIL() << "loaded";
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.file(), "mem/part.xml");
    EXPECT_EQ(e.line(), 3);  // the fourth object
    EXPECT_NE(std::string(e.what()).find("at most 3 objects"), std::string::npos) << e.what();
  }
  options.limits = {};
  options.limits.max_imported_files = 1;
  try {
    load_world_file("mem/world.xml", options);
    FAIL() << "loaded";
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 3);  // the second import
    EXPECT_NE(std::string(e.what()).find("at most 1 files"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_world_file("mem/none.xml", options), WorldFileError);
}

TEST(WorldBounds, TheShippedWorldsKeepTheBounds) {
  for (const char* file : {"DemoWorld_v1.xml", "small_room.xml", "ramps.xml", "liftability.xml",
                           "goals/demonstrator.xml", "goals/door_open.xml", "goals/stiff_switch.xml", "goals/push_to_switch.xml", "behaviour_trials.xml"}) {
    EXPECT_NO_THROW(bounds::check_world(shipped_world(file))) << file;
  }
}

}  // namespace
}  // namespace macsim::test
