// The world's broad phase (sim_core/src/broad_phase.cpp) finds the pairs ODE's own sweep and
// prune finds, as geoms start and stop moving; a world's sleeping objects stay collidable after
// an edit moves them.
#include "broad_phase.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "macsim/sim_core/world.h"
#include "ode_support.h"
#include "support/world_helpers.h"

namespace macsim::detail {
namespace {

using Pair = std::pair<dGeomID, dGeomID>;

Pair ordered(dGeomID a, dGeomID b) { return a < b ? Pair{a, b} : Pair{b, a}; }

/// What any collision of a world must see: pairs whose boxes overlap, at least one on an awake
/// body, never two geoms of one body.
bool wanted(dGeomID a, dGeomID b) {
  dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
  if (ba && ba == bb) return false;
  return (ba && dBodyIsEnabled(ba)) || (bb && dBodyIsEnabled(bb));
}

void collect(void* data, dGeomID a, dGeomID b) {
  if (wanted(a, b)) static_cast<std::vector<Pair>*>(data)->push_back(ordered(a, b));
}

class BroadPhaseScene : public ::testing::Test {
 protected:
  BroadPhaseScene() {
    dInitODE2(0);
    world_ = dWorldCreate();
    space_ = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ);
    geoms_.push_back(dCreatePlane(space_, 0, 0, 1, 0));
    std::uniform_real_distribution<double> size(0.05, 0.5);
    for (int i = 0; i < 400; ++i) {
      dGeomID g = i % 3 == 0   ? dCreateBox(space_, size(rng_), size(rng_), size(rng_))
                  : i % 3 == 1 ? dCreateCylinder(space_, size(rng_) / 2, size(rng_))
                               : dCreateSphere(space_, size(rng_) / 2);
      if (i % 75 == 0) dGeomBoxSetLengths(g, 4.0, 0.2, 1.0);  // a wall: more cells than most
      if (i % 4 != 0) {  // three in four on bodies, some with two geoms
        dBodyID body = dBodyCreate(world_);
        dGeomSetBody(g, body);
        if (i % 8 == 1) {
          dGeomID second = dCreateSphere(space_, 0.1);
          dGeomSetBody(second, body);
          dGeomSetOffsetPosition(second, 0.2, 0, 0);
          geoms_.push_back(second);
        }
        bodies_.push_back(body);
      }
      geoms_.push_back(g);
    }
    std::shuffle(geoms_.begin(), geoms_.end(), rng_);  // the tracked order is the caller's
    scatter();
  }
  ~BroadPhaseScene() override {
    dSpaceDestroy(space_);
    dWorldDestroy(world_);
  }

  /// Puts every geom somewhere new, sends about half the bodies to sleep.
  void scatter() {
    std::uniform_real_distribution<double> at(-3.0, 3.0), height(0.0, 1.0);
    std::bernoulli_distribution asleep(0.5);
    for (dGeomID g : geoms_) {
      if (dGeomGetClass(g) == dPlaneClass || dGeomGetBody(g)) continue;
      dGeomSetPosition(g, at(rng_), at(rng_), height(rng_));
    }
    for (dBodyID b : bodies_) {
      dBodySetPosition(b, at(rng_), at(rng_), height(rng_));
      if (asleep(rng_)) {
        dBodyDisable(b);
      } else {
        dBodyEnable(b);
      }
    }
  }

  /// Moves the awake bodies a little, wakes a few sleepers and sends a few to sleep, as steps do.
  void step_like() {
    std::uniform_real_distribution<double> nudge(-0.3, 0.3);
    std::bernoulli_distribution flip(0.1);
    for (dBodyID b : bodies_) {
      if (dBodyIsEnabled(b)) {
        const dReal* p = dBodyGetPosition(b);
        dBodySetPosition(b, p[0] + nudge(rng_), p[1] + nudge(rng_), p[2]);
      }
      if (flip(rng_)) {
        if (dBodyIsEnabled(b)) {
          dBodyDisable(b);
        } else {
          dBodyEnable(b);
        }
      }
    }
  }

  std::vector<Pair> ode_pairs() {
    std::vector<Pair> pairs;
    dSpaceCollide(space_, &pairs, &collect);
    std::sort(pairs.begin(), pairs.end());
    return pairs;
  }

  std::vector<Pair> broad_phase_pairs(BroadPhase& broad, std::vector<Pair>* in_order = nullptr) {
    std::vector<Pair> pairs;
    dSpaceClean(space_);
    broad.collide(&pairs, [](void* data, dGeomID a, dGeomID b) {
      static_cast<std::vector<Pair>*>(data)->push_back({a, b});
    });
    if (in_order) *in_order = pairs;
    for (auto& p : pairs) {
      EXPECT_TRUE(wanted(p.first, p.second)) << "a pair of still geoms, or of one body";
      p = ordered(p.first, p.second);
    }
    std::sort(pairs.begin(), pairs.end());
    return pairs;
  }

  std::mt19937 rng_{11};
  dWorldID world_;
  dSpaceID space_;
  std::vector<dGeomID> geoms_;
  std::vector<dBodyID> bodies_;
};

TEST_F(BroadPhaseScene, FindsThePairsOdesSweepAndPruneFinds) {
  BroadPhase broad;
  broad.track(geoms_);
  std::size_t compared = 0;
  for (int round = 0; round < 20; ++round) {
    const auto expected = ode_pairs();
    const auto found = broad_phase_pairs(broad);
    ASSERT_EQ(found, expected) << "round " << round;
    compared += expected.size();
    step_like();
  }
  EXPECT_GT(compared, 2000u);  // the scene is crowded enough to mean something
  EXPECT_GT(broad.still_count(), 50u);
}

TEST_F(BroadPhaseScene, PairsComeInTheTrackedOrderEarlierFirst) {
  BroadPhase broad;
  broad.track(geoms_);
  std::vector<Pair> in_order;
  broad_phase_pairs(broad, &in_order);
  ASSERT_GT(in_order.size(), 50u);
  auto index = [this](dGeomID g) {
    return std::find(geoms_.begin(), geoms_.end(), g) - geoms_.begin();
  };
  for (std::size_t i = 0; i < in_order.size(); ++i) {
    EXPECT_LT(index(in_order[i].first), index(in_order[i].second));
    if (i > 0) {
      EXPECT_LT(std::pair(index(in_order[i - 1].first), index(in_order[i - 1].second)),
                std::pair(index(in_order[i].first), index(in_order[i].second)));
    }
  }
  // The same geoms in the same places give the same sequence, whatever happened before.
  BroadPhase again;
  step_like();
  again.track(geoms_);
  broad.track(geoms_);
  std::vector<Pair> first, second;
  broad_phase_pairs(broad, &first);
  broad_phase_pairs(again, &second);
  EXPECT_EQ(first, second);
}

}  // namespace
}  // namespace macsim::detail

namespace macsim::test {
namespace {

TEST(BroadPhaseWorld, ASleepingBoxMovedByAnEditStillCarriesWhatFallsOnIt) {
  WorldSpec spec;
  spec.name = "two_boxes";
  spec.materials.push_back(MaterialSpec{});
  spec.materials.back().name = "default";
  spec.objects.push_back(primitive(Shape::Box, {0.2, 0.2, 0.2}, {0, 0, 0.1}));
  spec.objects.back().name = "base";
  World world(spec);
  for (int i = 0; i < 300; ++i) world.step();
  const ObjectId base = *world.objects().find_object("base");
  ASSERT_FALSE(world.state().bodies.at(0).enabled) << "asleep before the move";
  ASSERT_TRUE(world.edit().set_position(base, {2.0, 0.0, 0.1}).ok());
  auto dropped =
      world.edit().create_object(primitive(Shape::Box, {0.1, 0.1, 0.1}, {2.0, 0.0, 0.5}));
  ASSERT_TRUE(dropped.ok());
  for (int i = 0; i < 1000; ++i) world.step();
  EXPECT_NEAR(world.objects().object_state(dropped.value).value.pose.position.z(), 0.25, 0.01)
      << "the dropped box rests on the base where the edit put it";
}

}  // namespace
}  // namespace macsim::test
