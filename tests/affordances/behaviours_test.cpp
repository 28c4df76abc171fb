// What the behaviours judge of a scene without a robot (where travel keeps off the switch), and
// what their code never reads (a family's name, the supervisor, the world state). (The behaviours themselves drive a robot: integration/kurt_demo_test.cpp plays them
// against macsim; the scene's atoms: scene_atoms_test.cpp.)
#include "macsim/affordances/behaviours.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "affordances/seen_thing.h"
#include "support/child_process.h"

namespace macsim::affordances {
namespace {

using test_scenes::seen;

TEST(Behaviours, TravelKeepsOffARaisedSwitchBeyondItsBaseAndDrivesOverAFlushPlate) {
  Scene scene;
  EXPECT_EQ(switch_keep_off(scene), 0.0);  // none seen
  scene.switch_platform = seen("switch", "yellow");
  scene.switch_platform->features["width_m"] = 0.28;  // the yellow of a raised platform
  // Its base (0.30 m square: 0.21 m to a corner) lies beyond the yellow seen.
  EXPECT_GT(switch_keep_off(scene), 0.22);
  EXPECT_LT(switch_keep_off(scene), 0.4);  // the way to put a can down on it stays free
  scene.switch_platform->features["width_m"] = 0.52;  // flush with the floor
  EXPECT_EQ(switch_keep_off(scene), 0.0);
}

}  // namespace
}  // namespace macsim::affordances

namespace macsim::affordances {
namespace {

// The rule of the goal families (worlds/goals/): the robot acts on what its own sensors perceive.
// The behaviours, the planner and kurt_plan name no family (no layout is special-cased) and read
// neither the supervisor nor the world state nor the ground truth (pictures for people are
// allowed: they decide nothing).
TEST(Behaviours, NeitherTheyNorKurtPlanNameAFamilyOrReadTheSupervisorOrTheWorldState) {
  const std::vector<std::string> forbidden = {
      "door_open", "push_to_switch", "stiff_switch", "cluttered_way", "worlds/goals",
      "SupervisorClient", "macsim/client/world_state.h", "WorldState", "kWorld", "ground_truth"};
  int files = 0;
  for (const char* folder : {"affordances/src", "affordances/include/macsim/affordances",
                             "examples/kurt_plan"}) {
    for (const auto& f : std::filesystem::directory_iterator(macsim::test::source(folder))) {
      std::ifstream in(f.path());
      std::stringstream text;
      text << in.rdbuf();
      ++files;
      for (const auto& word : forbidden)
        EXPECT_EQ(text.str().find(word), std::string::npos) << f.path() << " names " << word;
    }
  }
  EXPECT_GE(files, 20);  // the folders were found and read
}

}  // namespace
}  // namespace macsim::affordances
