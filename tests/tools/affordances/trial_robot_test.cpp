// Hand-checked physical cases of the stack and traverse trials, played by the trial controller
// against a real lock-step simulator: what the robot can cross, pass and stack is what the
// physics of the KURT3D (wheels of 6 cm radius, a body 0.325 m wide) says it should be.
#include "trial_robot.h"

#include <gtest/gtest.h>

#include <memory>

#include "support/child_process.h"
#include "support/test_domain.h"

namespace affordances {
namespace {

using namespace std::chrono_literals;

const Material& material(const std::string& name) {
  for (const auto& m : materials()) {
    if (name == m.name) return m;
  }
  throw std::invalid_argument("no material " + name);
}

void set_material(TrialSpec& t, const std::string& name) {
  const Material& m = material(name);
  t.material = m.name;
  t.colour = m.colour;
  t.density = m.density;
  t.friction = m.friction;
  t.magnetizable = m.magnetizable;
}

/// An obstacle of the traverse trials, its near edge 0.68 m ahead, on the robot's axis.
TrialSpec obstacle(Shape shape, std::array<double, 3> size, double gap = 0) {
  TrialSpec t = make_trial(Affordance::Traverse, Generator::Material, 1);
  t.shape = shape;
  t.size = size;
  t.gap = gap;
  t.yaw = 0;
  t.fixed = shape != Shape::LyingCylinder && shape != Shape::Sphere;
  set_material(t, "wood");
  t.x = 0.68 + t.reach_ahead();
  t.y = 0;
  t.mass = t.density * t.volume();
  return t;
}

/// A base of the stack trials with a 6 cm tin box to carry onto it.
TrialSpec base(Shape shape, std::array<double, 3> size, const std::string& material_name) {
  TrialSpec t = make_trial(Affordance::Stack, Generator::Material, 1);
  t.shape = shape;
  t.size = size;
  set_material(t, material_name);
  t.x = 1.0;
  t.y = 0;
  t.mass = t.density * t.volume();
  t.carried.shape = Shape::Box;
  t.carried.size = {0.06, 0.06, 0.05};
  t.carried.mass = t.carried.density * 0.06 * 0.06 * 0.05;
  return t;
}

class TrialRobotCases : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    domain_ = macsim::test::unique_test_domain();
    simulator_ = std::make_unique<macsim::test::ChildProcess>(std::vector<std::string>{
        macsim::test::bin("macsim"), "--world",
        macsim::test::source("worlds/affordance_trials.xml"), "--domain", std::to_string(domain_),
        "--lockstep", "--camera-rate", "1.25", "--cameras", "320x240"});
    InstanceOptions options;
    options.domain = domain_;
    robot_ = std::make_unique<TrialRobot>(options);
    robot_->connect(30s);
  }
  static void TearDownTestSuite() {
    robot_.reset();
    simulator_.reset();
  }
  static TrialRecord run(const TrialSpec& spec) { return robot_->run(spec); }

  static int domain_;
  static std::unique_ptr<macsim::test::ChildProcess> simulator_;
  static std::unique_ptr<TrialRobot> robot_;
};
int TrialRobotCases::domain_ = -1;
std::unique_ptr<macsim::test::ChildProcess> TrialRobotCases::simulator_;
std::unique_ptr<TrialRobot> TrialRobotCases::robot_;

TEST_F(TrialRobotCases, ALyingCylinderAndASphereRollAwayAndAreTraversable) {
  const auto cylinder = run(obstacle(Shape::LyingCylinder, {0.12, 0.12, 0.3}));
  EXPECT_EQ(cylinder.outcome.label, "traversable") << csv_row(cylinder);
  const auto sphere = run(obstacle(Shape::Sphere, {0.15, 0.15, 0.15}));
  EXPECT_EQ(sphere.outcome.label, "traversable") << csv_row(sphere);
}

TEST_F(TrialRobotCases, AnUprightCylinderTallerThanTheBumperIsNotTraversable) {
  const auto r = run(obstacle(Shape::Cylinder, {0.15, 0.15, 0.3}));
  EXPECT_EQ(r.outcome.label, "not_traversable") << csv_row(r);
  EXPECT_LT(r.outcome.passed, -0.2);           // stopped at it
  EXPECT_GT(r.percept.corridor_height, 0.25);  // and the cloud showed how high it is
}

TEST_F(TrialRobotCases, ATwoCentimetreJoistIsCrossedATwelveCentimetreStepIsNot) {
  const auto joist = run(obstacle(Shape::Joist, {0.05, 1.0, 0.02}));
  EXPECT_EQ(joist.outcome.label, "traversable") << csv_row(joist);
  EXPECT_GT(joist.outcome.rise, 0.01);  // over it, not around it
  const auto step = run(obstacle(Shape::Step, {0.3, 1.0, 0.12}));
  EXPECT_EQ(step.outcome.label, "not_traversable") << csv_row(step);
}

TEST_F(TrialRobotCases, APassageFiveCentimetresWiderThanTheRobotIsPassedOneNarrowerIsNot) {
  const auto wide = run(obstacle(Shape::Passage, {0.3, 0.375, 0.4}, 0.375));
  EXPECT_EQ(wide.outcome.label, "traversable") << csv_row(wide);
  EXPECT_NEAR(wide.percept.free_width, 0.375, 0.05);
  const auto narrow = run(obstacle(Shape::Passage, {0.3, 0.275, 0.4}, 0.275));
  EXPECT_EQ(narrow.outcome.label, "not_traversable") << csv_row(narrow);
  EXPECT_LT(narrow.percept.free_width, 0.33);
}

TEST_F(TrialRobotCases, ABoxOnABoxStacksABoxOnASphereDoesNot) {
  const auto box = run(base(Shape::Box, {0.2, 0.2, 0.12}, "wood"));
  EXPECT_EQ(box.outcome.label, "stacked") << csv_row(box);
  EXPECT_NEAR(box.outcome.settle, 0.0, 0.005);
  // What the magnet found: it catches 1 cm away, and the wait ends at the next tick.
  EXPECT_NEAR(box.percept.carried_height, 0.06, 0.012);
  const auto sphere = run(base(Shape::Sphere, {0.2, 0.2, 0.2}, "steel"));
  EXPECT_NE(sphere.outcome.label, "stacked") << csv_row(sphere);
  // The carried box came off the top, or leans on it (held by friction, not level).
  EXPECT_TRUE(sphere.outcome.settle < -0.015 || sphere.outcome.a_tilt >= 0.2) << csv_row(sphere);
}

}  // namespace
}  // namespace affordances
