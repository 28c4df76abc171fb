// PDDL text: what is written reads back to the same domain and problem (both dialects), the
// shipped hand-written domain reads, and every kind of fault is refused naming its file and line.
#include "macsim/affordances/pddl.h"

#include <gtest/gtest.h>

#include <string>

#include "support/child_process.h"

namespace macsim::affordances::pddl {
namespace {

using macsim::test::source;

const std::string kByHand = "affordances/domains/kurt3d_room_by_hand.pddl";

Domain small_domain() {
  Domain d;
  d.name = "room";
  d.note = "two lines\nof note";
  d.types = {{"location", "object"}, {"thing", "location"}, {"switch", "location"}};
  d.predicates = {{"robot-at", {{"?l", "location"}}},
                  {"holding", {{"?t", "thing"}}},
                  {"hand-free", {}},
                  {"pressed", {{"?s", "switch"}}},
                  {"hue-le-214p5", {{"?t", "thing"}}}};
  Operator lift;
  lift.name = "lift-leaf-3";
  lift.note = "lift: hue <= 214.5, 40 trials";
  lift.parameters = {{"?t", "thing"}};
  lift.requires_true = {{"robot-at", {"?t"}}, {"hand-free", {}}};
  lift.requires_false = {{"hue-le-214p5", {"?t"}}};
  lift.outcomes = {{0.875, {{"holding", {"?t"}}}, {{"hand-free", {}}}},
                   {0.1, {}, {{"robot-at", {"?t"}}}}};
  Operator go;
  go.name = "go";
  go.parameters = {{"?a", "location"}, {"?b", "location"}};
  go.requires_true = {{"robot-at", {"?a"}}};
  go.outcomes = {{1.0, {{"robot-at", {"?b"}}}, {{"robot-at", {"?a"}}}}};
  d.operators = {lift, go};
  return d;
}

Problem small_problem() {
  Problem p;
  p.name = "one-can";
  p.domain = "room";
  p.note = "from a look at 12.5 s";
  p.objects = {{"start", "location"}, {"can-1", "thing"}, {"switch-1", "switch"}};
  p.init = {{"robot-at", {"start"}}, {"hand-free", {}}};
  p.goal_true = {{"holding", {"can-1"}}};
  p.goal_false = {{"pressed", {"switch-1"}}};
  return p;
}

TEST(Pddl, AProbabilisticDomainReadsBackAsWritten) {
  const Domain d = small_domain();
  const std::string text = write(d, Dialect::Probabilistic);
  EXPECT_NE(text.find("(probabilistic"), std::string::npos);
  EXPECT_NE(text.find("; lift: hue <= 214.5, 40 trials"), std::string::npos);
  Domain back = read_domain(text, "room.ppddl");
  back.note = d.note;  // comments are for people; the reader skips them
  for (auto& op : back.operators) op.note = d.operators[&op - back.operators.data()].note;
  EXPECT_EQ(back, d);
}

TEST(Pddl, AStripsDomainKeepsEachOperatorsMostLikelyOutcome) {
  const std::string text = write(small_domain(), Dialect::Strips);
  EXPECT_EQ(text.find("probabilistic-effects"), std::string::npos);
  EXPECT_NE(text.find("; the most likely of 2 outcomes, p = 0.875"), std::string::npos);
  const Domain back = read_domain(text, "room.pddl");
  ASSERT_EQ(back.operators.size(), 2U);
  ASSERT_EQ(back.operators[0].outcomes.size(), 1U);
  EXPECT_EQ(back.operators[0].outcomes[0].add, small_domain().operators[0].outcomes[0].add);
  EXPECT_EQ(back.operators[0].outcomes[0].probability, 1.0);
}

TEST(Pddl, AProblemReadsBackAsWritten) {
  const Domain d = small_domain();
  const Problem p = small_problem();
  Problem back = read_problem(write(p), "one-can.pddl", d);
  back.note = p.note;
  EXPECT_EQ(back, p);
}

TEST(Pddl, TheHandWrittenDomainReadsAndWritesBackToItself) {
  const Domain d = load_domain(source(kByHand));
  EXPECT_EQ(d.name, "kurt3d-room");
  EXPECT_EQ(d.operators.size(), 6U);
  EXPECT_TRUE(is_a(d, "switch", "location"));
  EXPECT_FALSE(is_a(d, "thing", "place"));
  Domain again = read_domain(write(d, Dialect::Probabilistic), "again.ppddl");
  EXPECT_EQ(again, d);
}

/// Expects reading `text` as a domain to fail with a message starting "FILE:LINE: " and holding
/// `what`.
void expect_domain_error(const std::string& text, int line, const std::string& what) {
  try {
    read_domain(text, "bad.pddl");
    ADD_FAILURE() << "read without error:\n" << text;
  } catch (const PddlError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("bad.pddl:" + std::to_string(line) + ": ", 0), 0U) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

TEST(Pddl, ABadDomainIsRefusedNamingItsLine) {
  const std::string head =
      "(define (domain d)\n"            // 1
      "  (:types thing - object)\n"     // 2
      "  (:predicates (p ?x - thing) (q))\n";  // 3
  expect_domain_error("", 1, "empty");
  expect_domain_error(head, 1, "never closed");
  expect_domain_error(head + ")\n)", 5, "closes nothing");
  expect_domain_error(head + "  (:action a :parameters (?x - thing)\n    :precondition (r ?x)\n"
                             "    :effect (q)))",
                      5, "unknown predicate 'r'");
  expect_domain_error(head + "  (:action a :parameters (?x - thing)\n    :precondition (p ?x ?x)"
                             "\n    :effect (q)))",
                      5, "takes 1 argument(s), given 2");
  expect_domain_error(head + "  (:action a :parameters (?x - thing)\n    :precondition (p ?y)"
                             "\n    :effect (q)))",
                      5, "'?y' is not a parameter of action a");
  expect_domain_error(head + "  (:action a :parameters (?x - widget)\n    :effect (q)))", 4,
                      "unknown type 'widget'");
  expect_domain_error(head + "  (:action a :parameters (?x - thing)\n    :precondition (or (p ?x)"
                             " (q))\n    :effect (q)))",
                      5, "not STRIPS");
  expect_domain_error(head + "  (:action a :parameters ()\n    :effect (probabilistic 0.7 (q) 0.6"
                             " (and))))",
                      5, "add up to 1.3");
  expect_domain_error(head + "  (:action a :parameters ()\n    :effect (probabilistic nan (q))))",
                      5, "'nan' is no probability");
  expect_domain_error(head + "  (:action a :parameters ()\n    :effect (probabilistic 1e308 (q))))",
                      5, "no probability");
  expect_domain_error(head + "  (:action a :parameters ()\n    :precondition (q)))", 4,
                      "has no :effect");
  expect_domain_error(head + "  (:action a :parameters () :effect (q))\n"
                             "  (:action a :parameters () :effect (q)))",
                      5, "action 'a' twice");
  expect_domain_error("(define (domain d)\n  (:requirements :strips :fluents))", 2,
                      "':fluents' is not supported");
  expect_domain_error("(define (domain d)\n  (:types a - b b - a))", 2, "cycle");
  expect_domain_error("(define (domain d)\n  (:types a - nothing))", 2, "unknown 'nothing'");
  expect_domain_error(std::string("(define (domain d)\n  (:predicates (p\x01)))"), 2,
                      "printable ASCII");
}

TEST(Pddl, ABadProblemIsRefusedNamingItsLine) {
  const Domain d = small_domain();
  const auto expect_error = [&](const std::string& text, int line, const std::string& what) {
    try {
      read_problem(text, "p.pddl", d);
      ADD_FAILURE() << "read without error:\n" << text;
    } catch (const PddlError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("p.pddl:" + std::to_string(line) + ": ", 0), 0U) << message;
      EXPECT_NE(message.find(what), std::string::npos) << message;
    }
  };
  const std::string head = "(define (problem p)\n  (:domain room)\n  (:objects c - thing s - switch)\n";
  expect_error("(define (problem p)\n  (:domain other))", 2, "of domain 'other'");
  expect_error(head + "  (:init (holding d))\n  (:goal (hand-free)))", 4, "unknown object 'd'");
  expect_error(head + "  (:init (pressed c))\n  (:goal (hand-free)))", 4,
               "'c' of type thing, not a switch");
  expect_error(head + "  (:init (not (hand-free)))\n  (:goal (hand-free)))", 4, "(not ...) in :init");
  expect_error(head + "  (:init)\n  (:goal (flying c)))", 5, "unknown predicate 'flying'");
  expect_error(head + "  (:init))", 1, "no (:goal");
  expect_error("(define (problem p)\n  (:domain room)\n  (:objects c - thing c - switch)\n"
               "  (:goal (hand-free)))",
               3, "object 'c' twice");
}

TEST(Pddl, AFileThatCannotBeReadIsNamed) {
  EXPECT_THROW(load_domain("/nonexistent/domain.pddl"), PddlError);
  try {
    load_domain("/nonexistent/domain.pddl");
  } catch (const PddlError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/domain.pddl"), std::string::npos);
  }
}

}  // namespace
}  // namespace macsim::affordances::pddl
