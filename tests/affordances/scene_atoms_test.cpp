// What the behaviours report, said in the room's vocabulary: a scene's atoms as the demonstrator's
// scenes change it, and those atoms make problems of the hand-written domain that plan what is
// left to do.
#include "macsim/affordances/scene_atoms.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "affordances/seen_thing.h"
#include "macsim/affordances/planner.h"
#include "support/child_process.h"

namespace macsim::affordances {
namespace {

using pddl::Atom;

using test_scenes::seen;

bool has(const std::vector<Atom>& atoms, const Atom& a) {
  return std::find(atoms.begin(), atoms.end(), a) != atoms.end();
}

/// The plan of the hand-written domain from a scene to "beyond the door".
std::vector<std::string> plan_from(const Scene& scene) {
  static const pddl::Domain room =
      pddl::load_domain(macsim::test::source("affordances/domains/kurt3d_room_by_hand.pddl"));
  pddl::Problem p;
  p.name = "scene";
  p.domain = room.name;
  p.objects = {{"start", "place"}, {"switch", "switch"}, {"door", "door"}};
  for (const auto& t : scene.things)
    if (!t.lost) p.objects.push_back({t.name, "thing"});  // as kurt_plan's problems
  p.init = scene_atoms(scene);
  p.goal_true = {{"beyond", {"door"}}};
  const PlanResult r = plan(room, p);
  std::vector<std::string> steps;
  if (r.plan)
    for (const auto& s : r.plan->steps) steps.push_back(s.text());
  return steps;
}

TEST(SceneAtoms, TheSceneSaysWhereTheRobotIsAndWhatItHolds) {
  Scene scene;
  EXPECT_EQ(scene_atoms(scene), (std::vector<Atom>{{"hand-free", {}}, {"robot-at", {"start"}}}));
  scene.things = {seen("blue_1", "blue"), seen("red_1", "red")};
  scene.switch_platform = seen("switch", "yellow");
  scene.at = "red_1";
  scene.holding = "red_1";
  const auto holding = scene_atoms(scene);
  EXPECT_TRUE(has(holding, {"holding", {"red_1"}}));
  EXPECT_FALSE(has(holding, {"hand-free", {}}));
  EXPECT_TRUE(has(holding, {"opens", {"switch", "door"}}));
  EXPECT_EQ(plan_from(scene),
            (std::vector<std::string>{"(go red_1 switch)", "(put-down red_1 switch door)",
                                      "(go switch door)", "(drive-through door)"}));
}

TEST(SceneAtoms, AtAThingItLostSightOfTheRobotPlansFromAPlaceOfItsOwn) {
  // A box pushed out of sight: the robot still stands where it was, and plans on from there
  // with the other box (a problem names no lost thing: kurt_plan leaves them out).
  Scene scene;
  SeenThing lost = seen("red_1", "red"), other = seen("red_2", "red");
  lost.kind = other.kind = Kind::Box;
  lost.lost = true;
  scene.things = {lost, other};
  scene.switch_platform = seen("switch", "yellow");
  scene.switch_platform->features["width_m"] = 0.5;
  scene.at = "red_1";
  const auto atoms = scene_atoms(scene);
  EXPECT_TRUE(has(atoms, {"robot-at", {"start"}}));
  EXPECT_FALSE(has(atoms, {"robot-at", {"red_1"}}));
  EXPECT_EQ(plan_from(scene), (std::vector<std::string>{"(go start red_2)", "(push red_2 switch door)",
                                                        "(go switch door)", "(drive-through door)"}));
}

TEST(SceneAtoms, ACanOnTheSwitchAndTheDoorsGapAreInTheScene) {
  Scene scene;
  scene.things = {seen("red_1", "red")};
  scene.switch_platform = seen("switch", "yellow");
  scene.on_switch = {"red_1"};
  scene.at = "switch";
  scene.door = SeenDoor{1.5, 0, 1, 0, 0.8};
  const auto atoms = scene_atoms(scene);
  EXPECT_TRUE(has(atoms, {"on", {"red_1", "switch"}}));
  EXPECT_TRUE(has(atoms, {"loaded", {"switch"}}));
  EXPECT_TRUE(has(atoms, {"open", {"door"}}));
  EXPECT_TRUE(has(atoms, {"hand-free", {}}));
  EXPECT_EQ(plan_from(scene),
            (std::vector<std::string>{"(go switch door)", "(drive-through door)"}));
  scene.beyond_door = true;
  EXPECT_TRUE(has(scene_atoms(scene), {"beyond", {"door"}}));
  EXPECT_TRUE(plan_from(scene).empty());
}

TEST(SceneAtoms, ABoxAndAFlushPlateMakeAPushPlanWhereNoCanCanBeLifted) {
  Scene scene;
  scene.things = {seen("blue_1", "blue"), seen("green_1", "green")};
  scene.things[0].tried = true;  // did not come up
  scene.things[1].kind = Kind::Box;
  scene.switch_platform = seen("switch", "yellow");
  scene.switch_platform->features["width_m"] = 0.3;  // raised: a box is no use
  auto atoms = scene_atoms(scene);
  EXPECT_TRUE(has(atoms, {"box", {"green_1"}}));
  EXPECT_FALSE(has(atoms, {"box", {"blue_1"}}));
  EXPECT_FALSE(has(atoms, {"flush", {"switch"}}));
  EXPECT_TRUE(plan_from(scene).empty());
  scene.switch_platform->features["width_m"] = 0.52;  // as wide as the flush plates
  EXPECT_TRUE(has(scene_atoms(scene), {"flush", {"switch"}}));
  EXPECT_EQ(plan_from(scene), (std::vector<std::string>{"(go start green_1)", "(push green_1 switch door)",
                                                        "(go switch door)", "(drive-through door)"}));
}

}  // namespace
}  // namespace macsim::affordances
