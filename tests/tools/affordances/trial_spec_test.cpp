#include "trial_spec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "support/child_process.h"
#include "trial_record.h"

namespace affordances {
namespace {

TEST(TrialSpec, TheSameSeedDrawsTheSameTrialAndOtherSeedsOthers) {
  for (auto a : {Affordance::Lift, Affordance::Push, Affordance::Climb}) {
    const TrialSpec x = make_trial(a, Generator::Material, 42),
                    y = make_trial(a, Generator::Material, 42);
    EXPECT_EQ(x.size, y.size);
    EXPECT_EQ(x.material, y.material);
    EXPECT_EQ(x.x, y.x);
    EXPECT_EQ(x.ramp_angle, y.ramp_angle);
    std::set<double> xs;
    for (uint64_t s = 1; s <= 50; ++s) xs.insert(make_trial(a, Generator::Material, s).x);
    EXPECT_EQ(xs.size(), 50u) << name(a);
  }
}

TEST(TrialSpec, LiftObjectsAreSmallEnoughForTheCraneAndStandOnTheLaserPlane) {
  int magnetizable = 0;
  for (uint64_t s = 1; s <= 400; ++s) {
    const TrialSpec t = make_trial(Affordance::Lift, Generator::Material, s);
    EXPECT_NE(t.shape, Shape::Ramp);
    for (double v : t.size) {
      EXPECT_GE(v, 0.04);
      EXPECT_LE(v, 0.11);
    }
    EXPECT_LE(std::abs(t.y), 0.015);
    EXPECT_NEAR(t.mass, t.density * t.volume(), 1e-12);
    magnetizable += t.magnetizable;
  }
  EXPECT_GT(magnetizable, 150);  // about half
  EXPECT_LT(magnetizable, 250);
}

TEST(TrialSpec, Figure11MakesBlueObjectsHeavyAndEveryOtherColourLight) {
  int blue = 0;
  for (uint64_t s = 1; s <= 300; ++s) {
    const TrialSpec t = make_trial(Affordance::Lift, Generator::Figure11, s);
    const bool is_blue = t.colour[2] > 0.8f && t.colour[0] < 0.2f && t.colour[1] < 0.3f;
    blue += is_blue;
    EXPECT_TRUE(t.magnetizable);
    if (is_blue) {
      EXPECT_GT(t.mass, 0.6) << "seed " << s;  // beyond what the hoist lifts
    } else {
      EXPECT_LT(t.mass, 0.25) << "seed " << s;
    }
  }
  EXPECT_GT(blue, 25);
  EXPECT_LT(blue, 80);
}

TEST(TrialSpec, RampsAreNoLongerThanTheirLimitAndRiseWithTheirAngle) {
  for (uint64_t s = 1; s <= 200; ++s) {
    const TrialSpec t = make_trial(Affordance::Climb, Generator::Material, s);
    ASSERT_EQ(t.shape, Shape::Ramp);
    EXPECT_GE(t.ramp_angle, 5 * M_PI / 180);
    EXPECT_LE(t.ramp_angle, 50 * M_PI / 180);
    EXPECT_LE(t.ramp_height / std::tan(t.ramp_angle), 1.2 + 1e-9);
    EXPECT_EQ(t.height(), t.ramp_height);
    EXPECT_EQ(t.volume(), 0.0);
  }
}

TEST(TrialSpec, StackBasesStandInTheLaserPlaneAndTheCarriedObjectIsLightTinWithinReach) {
  std::map<Shape, int> shapes;
  for (auto g : {Generator::Material, Generator::Balanced}) {
    for (uint64_t s = 1; s <= 400; ++s) {
      const TrialSpec t = make_trial(Affordance::Stack, g, s);
      ++shapes[t.shape];
      EXPECT_FALSE(t.fixed);
      EXPECT_LE(std::abs(t.y), 0.015);
      EXPECT_GE(t.x, 0.95);
      EXPECT_LE(t.height(), 0.25);
      const Carried& c = t.carried;
      EXPECT_EQ(c.material, "tin");
      EXPECT_TRUE(c.shape == Shape::Box || c.shape == Shape::Cylinder);
      EXPECT_LT(c.mass, 0.35) << "seed " << s;  // the hoist lifts about 0.5 kg with the magnet
      EXPECT_NEAR(std::hypot(c.x - 0.05, c.y), 0.5, 1e-9);  // the level boom's reach
      EXPECT_GT(c.y - c.size[0] / 2, 0.2);                  // beside the robot, not under it
    }
  }
  EXPECT_EQ(shapes.size(), 4u);  // box, cylinder, lying cylinder, sphere
}

TEST(TrialSpec, TraverseObstaclesStartBeyondTheMagnetAndOnlyRollingOnesAreFree) {
  std::map<Shape, int> shapes;
  for (uint64_t s = 1; s <= 900; ++s) {
    const TrialSpec t = make_trial(Affordance::Traverse, Generator::Material, s);
    ++shapes[t.shape];
    EXPECT_EQ(t.fixed, t.shape != Shape::LyingCylinder && t.shape != Shape::Sphere);
    const double near = t.shape == Shape::Ramp ? t.x : t.x - t.reach_ahead();
    EXPECT_GE(near, 0.62 - 1e-9) << "seed " << s;  // the magnet hangs 0.55 m ahead
    EXPECT_LE(near, 0.75 + 1e-9) << "seed " << s;
    if (t.shape == Shape::Passage || t.shape == Shape::Doorstep) {
      EXPECT_GT(t.gap, 0.19);
    }
    if (t.fixed) {
      EXPECT_EQ(t.mass, 0.0);
    }
  }
  EXPECT_EQ(shapes.size(), 9u);
  for (const auto& [shape, count] : shapes) EXPECT_GT(count, 60) << name(shape);
  // A lying cylinder across the way reaches its radius ahead, one along it half its length.
  TrialSpec t = make_trial(Affordance::Traverse, Generator::Material, 1);
  t.shape = Shape::LyingCylinder;
  t.size = {0.1, 0.1, 0.4};
  t.yaw = 0;
  EXPECT_NEAR(t.reach_ahead(), 0.05, 1e-12);
  t.yaw = M_PI / 2;
  EXPECT_NEAR(t.reach_ahead(), 0.2, 1e-12);
}

TEST(TrialSpec, BalancedTraverseDrawsPassagesAroundTheRobotsWidth) {
  int near_width = 0, passages = 0;
  for (uint64_t s = 1; s <= 900; ++s) {
    const TrialSpec t = make_trial(Affordance::Traverse, Generator::Balanced, s);
    if (t.shape != Shape::Passage) continue;
    ++passages;
    near_width += t.gap > 0.26 && t.gap < 0.42;
  }
  EXPECT_GT(near_width, passages * 0.55);  // uniform over 0.2-0.6 would give 40 %
}

TEST(TrialSpec, BalancedPushAndClimbDrawWhatMaterialRarelyGives) {
  // Material stalls about 4 % of pushes and slides back about 10 % of climbs.
  int lead = 0, ice = 0;
  for (uint64_t s = 1; s <= 600; ++s) {
    const TrialSpec push = make_trial(Affordance::Push, Generator::Balanced, s);
    if (push.material == "lead" && push.size[0] >= 0.14 && push.shape != Shape::LyingCylinder &&
        push.shape != Shape::Sphere)
      ++lead;
    const TrialSpec climb = make_trial(Affordance::Climb, Generator::Balanced, s);
    ice += climb.material == "ice";
    EXPECT_LE(climb.ramp_angle, 50 * M_PI / 180 + 1e-12);
  }
  EXPECT_NEAR(lead / 600.0, 1 / 3.0 + 1 / 21.0, 0.07);  // a third, and lead among the others
  EXPECT_NEAR(ice / 600.0, 0.5, 0.07);                  // gentle and steep ice ramps
}

TEST(TrialSpec, MaterialLiftTrialsAreDrawnAsTheRowsOfAnEarlierVersionSay) {
  // 300 lift trials written before stack, traverse and balanced came: the same objects now.
  const CsvTable rows = read_csv(macsim::test::source("tests/tools/affordances/lift_trials.csv"));
  ASSERT_EQ(rows.rows.size(), 300u);
  auto at = [&](const std::vector<std::string>& row, const char* column) {
    return row[*rows.column(column)];
  };
  for (const auto& row : rows.rows) {
    const TrialSpec t =
        make_trial(Affordance::Lift, Generator::Material, std::stoull(at(row, "seed")));
    EXPECT_EQ(name(t.shape), at(row, "shape"));
    EXPECT_EQ(t.material, at(row, "material"));
    EXPECT_NEAR(t.size[0], std::stod(at(row, "size_x")), 1e-8);
    EXPECT_NEAR(t.size[2], std::stod(at(row, "size_z")), 1e-8);
    EXPECT_NEAR(t.x, std::stod(at(row, "x")), 1e-8);
    EXPECT_NEAR(t.y, std::stod(at(row, "y")), 1e-8);
  }
}

TEST(TrialSpec, NamesGoBothWays) {
  for (auto a : {Affordance::Lift, Affordance::Push, Affordance::Climb, Affordance::Stack,
                 Affordance::Traverse})
    EXPECT_EQ(affordance_from_name(name(a)), a);
  for (auto g : {Generator::Material, Generator::Figure11, Generator::Balanced})
    EXPECT_EQ(generator_from_name(name(g)), g);
  EXPECT_FALSE(affordance_from_name("fly"));
  EXPECT_FALSE(generator_from_name(""));
}

}  // namespace
}  // namespace affordances
