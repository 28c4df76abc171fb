// Property test of the supervisor: random sequences of operations (create, destroy, move into
// each other, resize, set mass and density, magnetise, push, snapshot and restore, reset) on the
// demonstrator world, dispatched as macsim dispatches them, with steps in between; what must
// hold of any world is checked after every step. A failing sequence is shrunk to its shortest
// failing form and printed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <random>
#include <sstream>

#include "supervisor/supervisor_dispatch.h"
#include "support/supervisor_actions.h"
#include "support/world_helpers.h"
#include "support/world_invariants.h"

namespace macsim::test {
namespace {

namespace mm = macsim_msgs::msg::dds_;

/// Runs the sequence on a fresh demonstrator world, 10 steps after each operation; the index of
/// the operation after which an invariant broke and why, or nothing.
std::optional<std::pair<std::size_t, std::string>> first_failure(
    const std::vector<Action>& actions) {
  World world(shipped_world("DemoWorld_v1.xml"));
  SnapshotStore snapshots;
  for (std::size_t i = 0; i < actions.size(); ++i) {
    std::string said;
    const mm::SupervisorReply_ reply =
        dispatch(request_for(actions[i], world, said), world, snapshots);
    if (reply.code() == mm::ERR_UNKNOWN_OPERATION) return {{i, said + ": no such operation"}};
    for (int s = 0; s < 10; ++s) {
      world.step();
      if (auto broken = invariant_violation(world)) return {{i, said + ": " + *broken}};
    }
  }
  return std::nullopt;
}

TEST(SupervisorProperty, RandomOperationSequencesKeepEveryInvariant) {
  std::mt19937 rng(20261123);
  // 40 sequences (24,000 steps in all); the first N where the code runs under the sanitizers
  // (MACSIM_PROPERTY_SEQUENCES=N, ctest's asan shards).
  const char* fewer = std::getenv("MACSIM_PROPERTY_SEQUENCES");
  const int sequences = fewer ? std::clamp(std::atoi(fewer), 1, 40) : 40;
  for (int sequence = 0; sequence < sequences; ++sequence) {
    std::vector<Action> actions(60);
    for (auto& a : actions) a = {int(rng() % kKinds), uint32_t(rng())};
    if (auto failure = first_failure(actions)) {
      const std::vector<Action> shortest =
          shrink(actions, [](const auto& a) { return first_failure(a).has_value(); });
      std::ostringstream steps;
      World world(shipped_world("DemoWorld_v1.xml"));
      for (const auto& a : shortest) {
        std::string said;
        request_for(a, world, said);
        steps << "\n  " << said;
      }
      FAIL() << "sequence " << sequence << " broke after operation " << failure->first << ": "
             << failure->second << "\nshortest failing sequence (" << shortest.size()
             << " operations):" << steps.str();
    }
  }
}

TEST(SupervisorProperty, TheShrinkerFindsTheShortestFailingSequence) {
  // A property that fails as soon as any object was destroyed: the shrinker must keep exactly
  // one destroy from a long sequence (a check that the machinery above can fail and shrink).
  std::vector<Action> actions;
  for (int i = 0; i < 20; ++i) actions.push_back({i % 3 == 0 ? 1 : 8, uint32_t(i)});
  auto fails = [](const std::vector<Action>& a) {
    World world(shipped_world("DemoWorld_v1.xml"));
    const int count = world.objects().object_count();
    SnapshotStore snapshots;
    for (const auto& action : a) {
      std::string said;
      dispatch(request_for(action, world, said), world, snapshots);
    }
    return world.objects().object_count() < count;
  };
  ASSERT_TRUE(fails(actions));
  const std::vector<Action> shortest = shrink(actions, fails);
  ASSERT_EQ(shortest.size(), 1u);
  EXPECT_EQ(shortest[0].kind, 1);
}

}  // namespace
}  // namespace macsim::test
