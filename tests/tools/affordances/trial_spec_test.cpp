#include "trial_spec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

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

TEST(TrialSpec, NamesGoBothWays) {
  for (auto a : {Affordance::Lift, Affordance::Push, Affordance::Climb})
    EXPECT_EQ(affordance_from_name(name(a)), a);
  for (auto g : {Generator::Material, Generator::Figure11})
    EXPECT_EQ(generator_from_name(name(g)), g);
  EXPECT_FALSE(affordance_from_name("fly"));
  EXPECT_FALSE(generator_from_name(""));
}

}  // namespace
}  // namespace affordances
