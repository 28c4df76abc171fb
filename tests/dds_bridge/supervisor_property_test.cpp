// Property test of the supervisor: random sequences of operations (create, destroy, move into
// each other, resize, set mass and density, magnetise, push, snapshot and restore, reset) on the
// demonstrator world, dispatched as macsim dispatches them, with steps in between; what must
// hold of any world is checked after every step. A failing sequence is shrunk to its shortest
// failing form and printed.
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <sstream>

#include "macsim/client/supervisor_requests.h"
#include "supervisor/supervisor_dispatch.h"
#include "support/world_helpers.h"
#include "support/world_invariants.h"

namespace macsim::test {
namespace {

namespace mm = macsim_msgs::msg::dds_;
namespace rq = client::supervisor;

/// One operation, drawn from its own seed when it runs: objects are picked among those there
/// then, so any subsequence of a sequence is a valid sequence too (what shrinking needs).
struct Action {
  int kind;
  uint32_t seed;
};
constexpr int kKinds = 12;

mm::SupervisorRequest_ request_for(const Action& a, const World& world, std::string& said) {
  std::mt19937 rng(a.seed);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<>(lo, hi)(rng);
  };
  const auto ids = world.objects().object_ids();
  const uint32_t id = ids.empty() ? 0 : ids[rng() % ids.size()];
  const rq::Vec3 place{uniform(-1.5, 1.5), uniform(-1.5, 1.5), uniform(0.05, 1.0)};
  std::ostringstream text;
  mm::SupervisorRequest_ r;
  switch (a.kind) {
    case 0: {
      mm::Object_ o;
      mm::Component_ c;
      c.shape(rng() % 2 ? mm::SHAPE_SPHERE : mm::SHAPE_BOX);
      c.size({uniform(0.02, 0.2), uniform(0.02, 0.2), uniform(0.02, 0.2)});
      c.pose().orientation().w(1.0);
      c.color({0.5f, 0.5f, 0.5f, 1.0f});
      o.components().push_back(c);
      o.kind(mm::KIND_OBJECT);
      o.portable(true);
      o.pose().position().x(place[0]);
      o.pose().position().y(place[1]);
      o.pose().position().z(place[2]);
      o.pose().orientation().w(1.0);
      o.density(uniform(10, 5000));
      r = rq::create_object(o, rng() % 2);
      text << "create";
      break;
    }
    case 1:
      r = rq::destroy_object(id);
      text << "destroy";
      break;
    case 2:
      r = rq::set_position(id, place, rng() % 2);
      text << "set_position";
      break;
    case 3:
      r = rq::set_box_size(id, 0, {uniform(0.01, 0.4), uniform(0.01, 0.4), uniform(0.01, 0.4)},
                           rng() % 2);
      text << "set_box_size";
      break;
    case 4:
      r = rq::set_sphere_size(id, 0, uniform(0.01, 0.3), rng() % 2);
      text << "set_sphere_size";
      break;
    case 5:
      r = rq::set_mass(id, uniform(0.01, 50));
      text << "set_mass";
      break;
    case 6:
      r = rq::set_density(id, uniform(10, 20000));
      text << "set_density";
      break;
    case 7:
      r = rq::set_magnetizable(id, rng() % 2);
      text << "set_magnetizable";
      break;
    case 8:
      r = rq::add_force(id, {uniform(-100, 100), uniform(-100, 100), uniform(-100, 100)});
      text << "add_force";
      break;
    case 9:
      r = rq::save_snapshot("s");
      text << "save_snapshot";
      break;
    case 10:
      r = rq::restore_snapshot("s");
      text << "restore_snapshot";
      break;
    default:
      r = rq::reset(int32_t(rng() % 3));
      text << "reset";
      break;
  }
  text << " (object " << id << ", seed " << a.seed << ")";
  said = text.str();
  return r;
}

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

/// Drops operations one at a time while the sequence still `fails`.
std::vector<Action> shrink(std::vector<Action> actions,
                           const std::function<bool(const std::vector<Action>&)>& fails) {
  for (std::size_t i = 0; i < actions.size();) {
    std::vector<Action> shorter = actions;
    shorter.erase(shorter.begin() + long(i));
    if (fails(shorter)) {
      actions = std::move(shorter);
    } else {
      ++i;
    }
  }
  return actions;
}

TEST(SupervisorProperty, RandomOperationSequencesKeepEveryInvariant) {
  std::mt19937 rng(20261123);
  for (int sequence = 0; sequence < 40; ++sequence) {  // 24,000 steps in all
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
