// World::overlaps(): which objects and robots start inside each other, how deep, what is not an
// overlap (resting contact, parts joined on purpose, fixed against fixed), and the report's lines.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <future>
#include <optional>

#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world_variation.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

const Overlap* find_pair(const OverlapReport& report, const std::string& a, const std::string& b) {
  for (const auto& o : report.pairs) {
    if ((o.first == a && o.second == b) || (o.first == b && o.second == a)) return &o;
  }
  return nullptr;
}

std::string listed(const OverlapReport& report) {
  std::string text;
  for (const auto& line : overlap_warnings(report, 50)) text += line + "\n";
  return text;
}

/// A world without robots holding `objects` (named obj_0, obj_1, ... unless named).
WorldSpec world_of(std::vector<ObjectSpec> objects) {
  WorldSpec spec = load_world_string("<WORLD><NAME>overlaps</NAME></WORLD>", "overlaps.xml");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (objects[i].name.empty()) objects[i].name = "obj_" + std::to_string(i);
    spec.objects.push_back(std::move(objects[i]));
  }
  return spec;
}

TEST(WorldOverlaps, NamesThePairsOfTheTestWorldWithTheirDepths) {
  const std::string file = source("tests/worlds/overlapping_objects.xml");
  const World world(load_world_file(file));
  const OverlapReport report = world.overlaps();
  EXPECT_FALSE(report.truncated);
  ASSERT_EQ(report.pairs.size(), 3u) << listed(report);

  const Overlap* boxes = find_pair(report, "box_a", "box_b");
  ASSERT_NE(boxes, nullptr) << listed(report);
  EXPECT_NEAR(boxes->depth, 0.1, 0.005);  // 0.2 m boxes 0.1 m apart
  EXPECT_EQ(boxes->first, "box_a");       // in the file's order
  EXPECT_EQ(boxes->source.file, file);
  EXPECT_GT(boxes->source.line, 10);

  // The chassis (0.215 m tall, bottom 0.06 m above the floor) around a 0.1 m box at 0.17 m:
  // pushed out upwards it would travel 0.275 - 0.12 = 0.155 m.
  const Overlap* robot = find_pair(report, "box_in_kurt", "kurt");
  ASSERT_NE(robot, nullptr) << listed(report);
  EXPECT_EQ(robot->first, "box_in_kurt");  // objects before robots
  EXPECT_NEAR(robot->depth, 0.155, 0.01);

  const Overlap* floor = find_pair(report, "sunk_ball", "ground");
  ASSERT_NE(floor, nullptr) << listed(report);
  EXPECT_NEAR(floor->depth, 0.05, 0.005);

  // Deepest first.
  EXPECT_EQ(report.pairs.front().first, "box_in_kurt");
  for (std::size_t i = 1; i < report.pairs.size(); ++i) {
    EXPECT_GE(report.pairs[i - 1].depth, report.pairs[i].depth);
  }
  // What only touches is no overlap: a box on the floor, a can on it, a box at a wall.
  for (const char* touching : {"floor_box", "can_on_box", "wall", "box_at_wall"}) {
    EXPECT_EQ(listed(report).find(touching), std::string::npos) << touching;
  }
  // A tolerance deeper than a pair leaves it out.
  const OverlapReport deep = world.overlaps(0.12);
  ASSERT_EQ(deep.pairs.size(), 1u) << listed(deep);
  EXPECT_EQ(deep.pairs.front().second, "kurt");
}

TEST(WorldOverlaps, WarningsNameFileLinePairAndDepth) {
  const std::string file = source("tests/worlds/overlapping_objects.xml");
  const OverlapReport report = World(load_world_file(file)).overlaps();
  const auto lines = overlap_warnings(report);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_NE(lines[1].find(file + ":"), std::string::npos) << lines[1];
  EXPECT_NE(lines[1].find(": warning: 'box_a' and 'box_b' start inside each other, 0.100 m deep"),
            std::string::npos)
      << lines[1];
  const auto capped = overlap_warnings(report, 1);
  ASSERT_EQ(capped.size(), 2u);
  EXPECT_NE(capped[1].find("and 2 more pairs"), std::string::npos) << capped[1];
  const std::string error = overlap_error(report, 1);
  EXPECT_NE(error.find("3 pairs of objects start inside each other: 'box_in_kurt' and 'kurt'"),
            std::string::npos)
      << error;
  EXPECT_TRUE(overlap_warnings(OverlapReport{}).empty());
}

TEST(WorldOverlaps, ShippedWorldsAndTheirEnvironmentsStartApart) {
  int worlds = 0;
  for (const char* folder : {"worlds", "tests/worlds"}) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(source(folder))) {
      if (entry.path().extension() != ".xml") continue;
      const std::string file = entry.path().string();
      std::optional<WorldSpec> spec;
      try {
        spec = load_world_file(file);
      } catch (const WorldFileError&) {
        // An environment file (imported by the worlds): built alone at the origin, with the
        // materials of one of the shipped environments.
        for (const char* materials : {"", "worlds/DemoEnvironment_v1/materials.xml",
                                      "worlds/AffordanceEnvironment/materials.xml"}) {
          const std::string import_materials =
              *materials ? "<IMPORT><ID>m</ID><NAME>" + source(materials) + "</NAME></IMPORT>" : "";
          try {
            spec = load_world_string("<WORLD><NAME>alone</NAME>" + import_materials +
                                         "<IMPORT><ID>env</ID><NAME>" + file +
                                         "</NAME></IMPORT></WORLD>",
                                     "alone.xml");
            break;
          } catch (const WorldFileError&) {
          }
        }
      }
      ASSERT_TRUE(spec) << file << " loads neither as a world nor as an environment";
      if (file.find("overlapping_objects") != std::string::npos) continue;
      const OverlapReport report = World(*spec).overlaps();
      EXPECT_TRUE(report.empty()) << file << ":\n" << listed(report);
      ++worlds;
      // Varied layouts (--seed) are placed with a clearance: apart too.
      if (!spec->variation) continue;
      for (uint32_t seed = 0; seed < 10; ++seed) {
        WorldSpec varied = *spec;
        vary_world(varied, seed);
        const OverlapReport seeded = World(std::move(varied)).overlaps();
        EXPECT_TRUE(seeded.empty()) << file << " seed " << seed << ":\n" << listed(seeded);
      }
    }
  }
  EXPECT_GE(worlds, 20);  // 6 worlds and their environments
}

TEST(WorldOverlaps, ObjectsRestingAfterASettleAreNotReported) {
  World world(shipped_world("DemoWorld_v1.xml"));
  run_for(world, 1.0);  // cans, blocks and the robot sink into what carries them and rest
  const OverlapReport report = world.overlaps();
  EXPECT_TRUE(report.empty()) << listed(report);
}

TEST(WorldOverlaps, JoinedFixedAndFrozenObjectsAreNoOverlap) {
  ObjectSpec wall = box_object({0, 0, 0.5}, {0.2, 2.0, 1.0}, false);
  wall.name = "wall";
  ObjectSpec pillar = box_object({0, 0, 0.5}, {0.3, 0.3, 1.0}, false);  // fixed in fixed
  pillar.name = "pillar";
  ObjectSpec frozen = box_object({0, 0.5, 0.5}, {0.3, 0.3, 0.3});  // held in place in the wall
  frozen.name = "frozen";
  frozen.frozen = true;
  ObjectSpec lid = box_object({2, 0, 0.1}, {0.2, 0.2, 0.2});  // slides in its (fixed) housing
  lid.name = "lid";
  ObjectSpec housing = box_object({2, 0, 0.15}, {0.3, 0.3, 0.3}, false);
  housing.name = "housing";
  ObjectSpec a = box_object({4, 0, 0.1}, {0.2, 0.2, 0.2});  // two portable parts on a slider
  a.name = "a";
  ObjectSpec b = box_object({4.1, 0, 0.1}, {0.2, 0.2, 0.2});
  b.name = "b";
  WorldSpec spec = world_of({wall, pillar, frozen, lid, housing, a, b});
  JointSpec lid_joint;
  lid_joint.name = "lid_joint";
  lid_joint.body1 = "lid";
  lid_joint.body2 = "housing";
  lid_joint.lo = -0.1;
  lid_joint.hi = 0.1;
  JointSpec ab = lid_joint;
  ab.name = "ab";
  ab.body1 = "b";
  ab.body2 = "a";
  ab.axis = {1, 0, 0};
  spec.joints = {lid_joint, ab};
  const OverlapReport report = World(spec).overlaps();
  EXPECT_TRUE(report.empty()) << listed(report);

  // Without its joints the lid is inside its housing and a inside b.
  spec.joints.clear();
  const OverlapReport loose = World(spec).overlaps();
  EXPECT_NE(find_pair(loose, "lid", "housing"), nullptr) << listed(loose);
  EXPECT_NE(find_pair(loose, "a", "b"), nullptr) << listed(loose);
  EXPECT_EQ(loose.pairs.size(), 2u) << listed(loose);
}

TEST(WorldOverlaps, ConcentricShapesThatOdeGivesNoContactForAreFound) {
  ObjectSpec can = cylinder_object({0, 0, 0.5}, 0.3, 1.0);
  ObjectSpec core = box_object({0, 0, 0.5}, {0.1, 0.1, 0.1});
  const OverlapReport report = World(world_of({can, core})).overlaps();
  ASSERT_EQ(report.pairs.size(), 1u) << listed(report);
  EXPECT_GT(report.pairs.front().depth, 0.25);  // the box's centre lies 0.3 m inside the can
}

TEST(WorldOverlaps, ManyObjectsAtOnePointAreCappedAndQuick) {
  std::vector<ObjectSpec> boxes(200, box_object({0, 0, 0.1}, {0.2, 0.2, 0.2}));
  const World world(world_of(boxes));
  const auto start = std::chrono::steady_clock::now();
  const OverlapReport report = world.overlaps();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(report.truncated);  // 19,900 pairs
  EXPECT_EQ(report.pairs.size(), kMaxOverlapPairs);
  EXPECT_LT(seconds, 5.0);
  const auto lines = overlap_warnings(report, 20);
  ASSERT_EQ(lines.size(), 21u);
  EXPECT_NE(lines.back().find("at least"), std::string::npos) << lines.back();
  EXPECT_EQ(overlap_error(report).rfind("at least 10000 pairs", 0), 0u) << overlap_error(report);

  // Spread on a grid, touching their neighbours: nothing, and near-linear work.
  std::vector<ObjectSpec> grid;
  for (int i = 0; i < 2500; ++i) {
    grid.push_back(box_object({(i % 50) * 0.2, (i / 50) * 0.2, 0.1}, {0.2, 0.2, 0.2}));
  }
  const World spread(world_of(grid));
  const OverlapReport apart = spread.overlaps();
  EXPECT_TRUE(apart.empty()) << listed(apart);
}

// A world loaded later (a request's load) is checked as the first one is: warnings into the
// log, or refused (the old world runs on) when the settings say so.
TEST(WorldOverlaps, ARunnerWarnsOfOrRefusesALoadedWorldWithOverlaps) {
  const std::string file = source("tests/worlds/overlapping_objects.xml");
  for (const bool refuse : {false, true}) {
    std::vector<std::string> log;
    RunSettings settings;
    settings.paused = true;
    settings.refuse_overlaps = refuse;
    const ScopedLogSink capture([&log](LogLevel, const std::string& line) { log.push_back(line); });
    Runner runner(shipped_world("small_room.xml"), settings);
    const World* before = &runner.world();
    std::promise<LoadOutcome> outcome;
    ASSERT_EQ(runner.load([file] { return load_world_file(file); },
                          [&outcome](const LoadOutcome& o) { outcome.set_value(o); }),
              LoadQueued::Yes);
    auto done = outcome.get_future();
    while (done.wait_for(std::chrono::milliseconds(0)) != std::future_status::ready) {
      runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::milliseconds(100));
      runner.apply_commands();
    }
    const LoadOutcome o = done.get();
    ASSERT_EQ(log.size(), 3u) << refuse;
    EXPECT_NE(log[1].find("'box_a' and 'box_b' start inside each other"), std::string::npos);
    if (refuse) {
      EXPECT_FALSE(o.ok);
      EXPECT_EQ(o.code, ErrorCode::BadFile);
      EXPECT_EQ(o.error.rfind(file + ":22: refused: 3 pairs of objects start inside each other: "
                                     "'box_in_kurt' and 'kurt' 0.155 m deep",
                              0),
                0u)
          << o.error;
      EXPECT_EQ(&runner.world(), before);  // the old world runs on
    } else {
      EXPECT_TRUE(o.ok) << o.error;
      EXPECT_EQ(runner.world().spec().name, "overlapping_objects");
    }
  }
}

}  // namespace
}  // namespace macsim::test

namespace macsim::test {
namespace {

/// The deepest overlap between two of the named things in a world built from `spec`.
double deepest_between_units(const WorldSpec& spec) {
  const World world(spec);
  double deepest = 0.0;
  for (const auto& o : world.overlaps().pairs) {
    if (o.first != "ground" && o.second != "ground") deepest = std::max(deepest, o.depth);
  }
  return deepest;
}

// A heap of boxes at one point is spread on the floor about it, each box clear of the others,
// and the same heap is always spread the same way.
TEST(PartOverlaps, AHeapOfBoxesAtOnePointIsSpreadAboutItAlwaysAlike) {
  std::vector<ObjectSpec> heap;
  for (int i = 0; i < 200; ++i) heap.push_back(box_object({1.0, 2.0, 0.05}, {0.1, 0.1, 0.1}));
  WorldSpec spec = world_of(heap), again = spec;
  const auto lines = part_overlaps(spec);
  ASSERT_EQ(lines.size(), 21u);
  EXPECT_NE(lines[0].find("warning: 'obj_"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("started 0.100 m deep inside 'obj_"), std::string::npos) << lines[0];
  EXPECT_EQ(lines.back().rfind("warning: ... and 1", 0), 0u) << lines.back();  // 179 or 180
  EXPECT_NE(lines.back().find(" more objects or robots moved apart"), std::string::npos);
  EXPECT_TRUE(World(spec).overlaps().empty()) << listed(World(spec).overlaps());
  double farthest = 0.0;
  for (const auto& o : spec.objects) {
    EXPECT_DOUBLE_EQ(o.pose.position.z(), 0.05);  // moved on the floor only
    farthest = std::max(farthest, (o.pose.position.head<2>() - Eigen::Vector2d(1, 2)).norm());
  }
  EXPECT_LT(farthest, 2.0);  // a compact disc about the point, not a line across the room
  part_overlaps(again);
  for (std::size_t i = 0; i < spec.objects.size(); ++i) {
    EXPECT_EQ(spec.objects[i].pose.position, again.objects[i].pose.position) << i;
  }
  // Parted once, there is nothing left to part.
  WorldSpec parted = spec;
  EXPECT_TRUE(part_overlaps(parted).empty());
}

// Robots at one point are parted from each other; an object inside a robot gives way, the robot
// stays; what is only shallowly inside, fixed, frozen or jointed stays where it is.
TEST(PartOverlaps, RobotsArePartedObjectsGiveWayAndWhatMayNotMoveStays) {
  WorldSpec spec = world_of({box_object({0, 0, 0.17}, {0.1, 0.1, 0.1}),
                             box_object({3.0, 0, 0.1}, {0.2, 0.2, 0.2}),
                             box_object({3.19, 0, 0.1}, {0.2, 0.2, 0.2}),  // 1 cm in: physics
                             box_object({-3.0, 0, 0.1}, {0.2, 0.2, 0.2}, false),
                             box_object({-3.05, 0, 0.1}, {0.2, 0.2, 0.2})});
  spec.objects[4].frozen = true;  // frozen inside a fixed box: neither moves
  for (int i = 0; i < 4; ++i) {
    RobotSpec robot;
    robot.name = "kurt_" + std::to_string(i);
    robot.type = "kurt3d";
    spec.robots.push_back(robot);
  }
  const WorldSpec before = spec;
  const auto lines = part_overlaps(spec);
  EXPECT_EQ(lines.size(), 5u);  // the box and the four robots
  EXPECT_EQ(spec.objects[1].pose.position, before.objects[1].pose.position);
  EXPECT_EQ(spec.objects[2].pose.position, before.objects[2].pose.position);
  EXPECT_EQ(spec.objects[3].pose.position, before.objects[3].pose.position);
  EXPECT_EQ(spec.objects[4].pose.position, before.objects[4].pose.position);
  EXPECT_NE(spec.objects[0].pose.position, before.objects[0].pose.position);
  const World world(spec);
  for (const auto& o : world.overlaps().pairs) {
    const bool robots = o.first.rfind("kurt_", 0) == 0 && o.second.rfind("kurt_", 0) == 0;
    EXPECT_FALSE(robots) << o.first << " " << o.second;
    EXPECT_FALSE(o.first == "obj_0" || o.second == "obj_0") << o.first << " " << o.second;
  }
  EXPECT_LT(deepest_between_units(spec), 0.02);  // what is left: the shallow pair
}

}  // namespace
}  // namespace macsim::test
