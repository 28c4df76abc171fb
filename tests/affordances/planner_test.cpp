// The planner on fixed problems of the hand-written room domain: the shortest plan in each kind
// of room, the likeliest of equally short plans, an unreachable goal reported with what cannot be
// made true, and a plan's steps applied one after the other reach the goal.
#include "macsim/affordances/planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "support/child_process.h"

namespace macsim::affordances {
namespace {

using macsim::test::source;
using pddl::Atom;

const pddl::Domain& room() {
  static const pddl::Domain d =
      pddl::load_domain(source("affordances/domains/kurt3d_room_by_hand.pddl"));
  return d;
}

/// A room with `things` things (the first `boxes` of them boxes), a switch and a door, the robot
/// at its start; the goal: beyond the door.
pddl::Problem room_problem(int things, int boxes = 0) {
  pddl::Problem p;
  p.name = "room";
  p.domain = "kurt3d-room";
  p.objects = {{"start", "place"}, {"switch-1", "switch"}, {"door-1", "door"}};
  p.init = {{"robot-at", {"start"}}, {"hand-free", {}}, {"opens", {"switch-1", "door-1"}}};
  for (int i = 0; i < things; ++i) {
    const std::string t = "thing-" + std::to_string(i + 1);
    p.objects.push_back({t, "thing"});
    if (i < boxes) p.init.push_back({"box", {t}});
  }
  p.goal_true = {{"beyond", {"door-1"}}};
  return p;
}

std::vector<std::string> names(const Plan& plan) {
  std::vector<std::string> out;
  for (const auto& s : plan.steps) out.push_back(s.text());
  return out;
}

/// Applies the plan's expected outcomes from the start, checking each step's preconditions.
void expect_plan_reaches_goal(const pddl::Problem& p, const Plan& plan) {
  std::vector<Atom> state = p.init;
  for (const auto& step : plan.steps) state = state_after(state, step);
  EXPECT_TRUE(satisfies(state, p));
}

TEST(Planner, TheDemonstratorsRoomTakesSixSteps) {
  const pddl::Problem p = room_problem(4);
  const PlanResult r = plan(room(), p);
  ASSERT_TRUE(r.plan) << r.reason;
  EXPECT_EQ(names(*r.plan),
            (std::vector<std::string>{"(go start thing-1)", "(lift thing-1)",
                                      "(go thing-1 switch-1)",
                                      "(put-down thing-1 switch-1 door-1)",
                                      "(go switch-1 door-1)", "(drive-through door-1)"}));
  EXPECT_DOUBLE_EQ(r.plan->probability, 0.5 * 0.8);
  expect_plan_reaches_goal(p, *r.plan);
}

TEST(Planner, TheApplicableStepsAreThoseWhosePreconditionsHoldAndThatChangeSomething) {
  pddl::Problem p = room_problem(2);
  std::vector<std::string> steps;
  for (const auto& s : applicable(room(), p)) steps.push_back(s.text());
  // From the start with the hand free: go anywhere else (never to the start itself); nothing to
  // lift, put down or drive through yet.
  EXPECT_EQ(steps, (std::vector<std::string>{"(go start switch-1)", "(go start door-1)",
                                             "(go start thing-1)", "(go start thing-2)"}));
  p.init = state_after(p.init, applicable(room(), p)[2]);  // at thing-1
  steps.clear();
  for (const auto& s : applicable(room(), p)) steps.push_back(s.text());
  EXPECT_NE(std::find(steps.begin(), steps.end(), "(lift thing-1)"), steps.end());
  EXPECT_EQ(std::find(steps.begin(), steps.end(), "(lift thing-2)"), steps.end());
  EXPECT_EQ(std::find(steps.begin(), steps.end(), "(go thing-1 thing-1)"), steps.end());
  for (const auto& s : applicable(room(), p)) {
    if (s.operator_name == "lift") {
      EXPECT_DOUBLE_EQ(s.probability, 0.5);  // the likelier of its outcomes
    }
  }
}

TEST(Planner, AnOpenDoorIsDrivenThroughAtOnce) {
  pddl::Problem p = room_problem(4);
  p.init.push_back({"open", {"door-1"}});
  const PlanResult r = plan(room(), p);
  ASSERT_TRUE(r.plan) << r.reason;
  EXPECT_EQ(names(*r.plan),
            (std::vector<std::string>{"(go start door-1)", "(drive-through door-1)"}));
}

TEST(Planner, ASwitchThatALoadDidNotPressTakesASecondThing) {
  // What the robot perceives after a put-down that left the door closed.
  pddl::Problem p = room_problem(3);
  p.init = {{"robot-at", {"switch-1"}}, {"hand-free", {}}, {"opens", {"switch-1", "door-1"}},
            {"on", {"thing-1", "switch-1"}}, {"loaded", {"switch-1"}}, {"tried", {"thing-1"}},
            {"tried", {"thing-2"}}};
  const PlanResult r = plan(room(), p);
  ASSERT_TRUE(r.plan) << r.reason;
  EXPECT_EQ(names(*r.plan),
            (std::vector<std::string>{"(go switch-1 thing-3)", "(lift thing-3)",
                                      "(go thing-3 switch-1)",
                                      "(put-down-on-loaded thing-3 switch-1 door-1)",
                                      "(go switch-1 door-1)", "(drive-through door-1)"}));
}

TEST(Planner, TwoThingsOnTheSwitchAndThroughTakeTenSteps) {
  pddl::Problem p = room_problem(5);
  p.goal_true = {{"on", {"thing-4", "switch-1"}}, {"on", {"thing-5", "switch-1"}}, {"beyond", {"door-1"}}};
  const PlanResult r = plan(room(), p);
  ASSERT_TRUE(r.plan) << r.reason;
  EXPECT_EQ(r.plan->steps.size(), 10U);
  expect_plan_reaches_goal(p, *r.plan);
}

TEST(Planner, AFlushSwitchIsPressedByPushingABox) {
  pddl::Problem p = room_problem(3, 3);
  p.init.push_back({"flush", {"switch-1"}});
  const PlanResult r = plan(room(), p);
  ASSERT_TRUE(r.plan) << r.reason;
  EXPECT_EQ(names(*r.plan),
            (std::vector<std::string>{"(go start thing-1)", "(push thing-1 switch-1 door-1)",
                                      "(go switch-1 door-1)", "(drive-through door-1)"}));
}

TEST(Planner, AnUnreachableGoalIsReportedWithWhatCannotBeMadeTrue) {
  // Only boxes, and no flush switch: nothing can be lifted or pushed onto the switch.
  const PlanResult r = plan(room(), room_problem(3, 3));
  EXPECT_FALSE(r.plan);
  EXPECT_FALSE(r.limit_reached);
  EXPECT_NE(r.reason.find("the goal cannot be reached"), std::string::npos) << r.reason;
  // Without a switch that opens the door no relaxed sequence reaches it either: it is named.
  pddl::Problem q = room_problem(2);
  q.init.erase(std::find(q.init.begin(), q.init.end(), Atom{"opens", {"switch-1", "door-1"}}));
  const PlanResult s = plan(room(), q);
  EXPECT_FALSE(s.plan);
  EXPECT_NE(s.reason.find("no sequence of steps makes (beyond door-1) true"), std::string::npos)
      << s.reason;
  // A goal on a predicate nothing changes, false at the start.
  q.goal_true = {{"flush", {"switch-1"}}};
  const PlanResult t = plan(room(), q);
  EXPECT_FALSE(t.plan);
  EXPECT_NE(t.reason.find("(flush switch-1) (nothing makes it true)"), std::string::npos) << t.reason;
}

TEST(Planner, AnOutcomeLessLikelyThanNothingIsPlannedOnAndSaidSo) {
  // A lift that comes up 40 % of the time is the only way: the plan counts on it, p = 0.4.
  pddl::Domain d = room();
  for (auto& op : d.operators)
    if (op.name == "lift") op.outcomes = {{0.4, op.outcomes[0].add, op.outcomes[0].remove}, {0.6, op.outcomes[1].add, {}}};
  const PlanResult r = plan(d, room_problem(1));
  ASSERT_TRUE(r.plan) << r.reason;
  EXPECT_EQ(r.plan->steps[1].text(), "(lift thing-1)");
  EXPECT_DOUBLE_EQ(r.plan->steps[1].probability, 0.4);
  EXPECT_DOUBLE_EQ(r.plan->probability, 0.4 * 0.8);
  // Below the floor it is not counted on.
  EXPECT_FALSE(plan(d, room_problem(1), PlanLimits{2'000'000, 10, 0.5}).plan);
}

TEST(Planner, AGoalMetAtTheStartNeedsNoStep) {
  pddl::Problem p = room_problem(1);
  p.goal_true = {{"hand-free", {}}};
  const PlanResult r = plan(room(), p);
  ASSERT_TRUE(r.plan) << r.reason;
  EXPECT_TRUE(r.plan->steps.empty());
}

TEST(Planner, OfEquallyShortPlansTheLikeliestIsTaken) {
  pddl::Domain d;
  d.name = "coin";
  d.types = {{"coin", "object"}};
  d.predicates = {{"won", {}}, {"fair", {{"?c", "coin"}}}};
  pddl::Operator toss;
  toss.name = "toss";
  toss.parameters = {{"?c", "coin"}};
  toss.requires_true = {{"fair", {"?c"}}};
  toss.outcomes = {{0.6, {{"won", {}}}, {}}};
  pddl::Operator bet = toss;
  bet.name = "bet";
  bet.outcomes = {{0.9, {{"won", {}}}, {}}};
  pddl::Operator gamble = toss;
  gamble.name = "gamble";
  gamble.outcomes = {{0.2, {{"won", {}}}, {}}};  // below PlanLimits::min_probability: never planned
  d.operators = {toss, bet, gamble};
  pddl::Problem p;
  p.name = "p";
  p.domain = "coin";
  p.objects = {{"c", "coin"}};
  p.init = {{"fair", {"c"}}};
  p.goal_true = {{"won", {}}};
  const PlanResult r = plan(d, p);
  ASSERT_TRUE(r.plan) << r.reason;
  ASSERT_EQ(r.plan->steps.size(), 1U);
  EXPECT_EQ(r.plan->steps[0].operator_name, "bet");
  EXPECT_DOUBLE_EQ(r.plan->probability, 0.9);
  d.operators = {gamble};
  EXPECT_FALSE(plan(d, p).plan);
}

TEST(Planner, TwentyThingsAndTheLongestPlanStayWithinTheSearchsLimit) {
  pddl::Problem p = room_problem(20);
  p.goal_true = {{"on", {"thing-19", "switch-1"}}, {"on", {"thing-20", "switch-1"}}, {"beyond", {"door-1"}}};
  const PlanResult r = plan(room(), p, PlanLimits{200'000, 30});
  ASSERT_TRUE(r.plan) << r.reason;
  EXPECT_EQ(r.plan->steps.size(), 10U);
  EXPECT_FALSE(r.limit_reached);
}

}  // namespace
}  // namespace macsim::affordances
