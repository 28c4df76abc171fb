// Effects learned from trials: the categories k-means and BIC find in perceived changes (as many
// as the changes have groups, matched to the labels), a tree whose rules hold on the trials, and a
// learned domain that plans as it reads back from its files. The trials here are drawn by a small
// model of the room's physics (a can comes up when light and magnetizable; a switch needs one or
// two things), with sensor noise, so that what is learned can be checked against what was drawn.
#include "macsim/affordances/effects.h"

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>
#include <set>

#include "macsim/affordances/planner.h"
#include "support/child_process.h"

namespace macsim::affordances {
namespace {

using pddl::Atom;

const pddl::Domain& vocabulary() {
  static const pddl::Domain d =
      pddl::load_domain(macsim::test::source("affordances/domains/kurt3d_room_by_hand.pddl"));
  return d;
}

/// Lift trials: hue in degrees and width in m as perceived; the can comes up (0.25-0.35 m, the
/// robot then holds it) when its hue is below 180 (steel colours) and it is narrower than 9 cm.
BehaviourTrials lift_trials(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> hue(0, 360), width(0.04, 0.14), noise(-0.01, 0.01);
  BehaviourTrials t;
  t.behaviour = "lift";
  t.parameters = {{"?t", "thing"}};
  t.features = {{"hue", "?t"}, {"width_m", "?t"}};
  t.changes = {{"height", 0.02}, {"distance", 0.02}};
  for (int i = 0; i < n; ++i) {
    EffectTrial trial;
    trial.seed = static_cast<std::uint64_t>(i + 1);
    const double h = hue(rng), w = width(rng);
    const bool up = h < 180 && w < 0.09;
    trial.before = {h, w};
    trial.change = {(up ? 0.3 : 0.0) + 5 * noise(rng), noise(rng)};
    trial.label = up ? "liftable" : "not_liftable";
    trial.atoms_before = {{"robot-at", {"?t"}}, {"hand-free", {}}};
    trial.atoms_after = trial.atoms_before;
    if (up) trial.atoms_after = {{"robot-at", {"?t"}}, {"holding", {"?t"}}};
    t.trials.push_back(std::move(trial));
  }
  return t;
}

/// Put-down trials on a switch: the platform sinks 2 cm when a thing already lay there, or on a
/// switch that is not stiff (half of them are, and the robot cannot tell).
BehaviourTrials put_down_trials(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.002, 0.002);
  std::bernoulli_distribution coin(0.5);
  BehaviourTrials t;
  t.behaviour = "put-down";
  t.parameters = {{"?t", "thing"}, {"?s", "switch"}, {"?d", "door"}};
  t.features = {{"width_m", "?t"}};
  t.changes = {{"platform_height", 0.005}, {"gap", 0.05}};
  for (int i = 0; i < n; ++i) {
    EffectTrial trial;
    trial.seed = static_cast<std::uint64_t>(i + 1);
    const bool loaded = coin(rng), stiff = coin(rng);
    const bool pressed = loaded || !stiff;
    trial.before = {0.06 + noise(rng)};
    trial.change = {(pressed ? -0.02 : 0.0) + noise(rng), (pressed ? 0.8 : 0.0) + 10 * noise(rng)};
    trial.label = pressed ? "pressed" : "not_pressed";
    trial.atoms_before = {{"holding", {"?t"}}, {"robot-at", {"?s"}}, {"opens", {"?s", "?d"}}};
    if (loaded) trial.atoms_before.push_back({"loaded", {"?s"}});
    trial.atoms_after = {{"hand-free", {}}, {"robot-at", {"?s"}}, {"opens", {"?s", "?d"}},
                         {"on", {"?t", "?s"}}, {"loaded", {"?s"}}};
    if (pressed) {
      trial.atoms_after.push_back({"pressed", {"?s"}});
      trial.atoms_after.push_back({"open", {"?d"}});
    }
    t.trials.push_back(std::move(trial));
  }
  return t;
}

/// Trips from a place to another: the robot ends where it went (about 1 m on, give or take 5 cm).
BehaviourTrials go_trials(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  BehaviourTrials t;
  t.behaviour = "go";
  t.parameters = {{"?from", "location"}, {"?to", "location"}};
  t.changes = {{"moved", 0.1}};
  for (int i = 0; i < n; ++i) {
    EffectTrial trial;
    trial.seed = static_cast<std::uint64_t>(i + 1);
    trial.change = {1.0 + noise(rng)};
    trial.label = "arrived";
    trial.atoms_before = {{"robot-at", {"?from"}}};
    trial.atoms_after = {{"robot-at", {"?to"}}};
    t.trials.push_back(std::move(trial));
  }
  return t;
}

TEST(Effects, TwoKindsOfChangeMakeTwoCategoriesThatMatchTheLabels) {
  const BehaviourTrials t = lift_trials(200, 1);
  const EffectCategories c = categorise(t);
  EXPECT_EQ(c.count, 2);
  EXPECT_GT(c.adjusted_rand, 0.95);
  // The commonest category is "nothing came up"; the other raised the thing 0.3 m and holds it.
  EXPECT_NEAR(c.centres[0][0], 0.0, 0.02);
  EXPECT_NEAR(c.centres[1][0], 0.3, 0.02);
  EXPECT_TRUE(c.effects[0].add.empty());
  EXPECT_EQ(c.effects[1].add, (std::vector<Atom>{{"holding", {"?t"}}}));
  EXPECT_EQ(c.effects[1].remove, (std::vector<Atom>{{"hand-free", {}}}));
  EXPECT_EQ(c.silhouette.size(), 5U);  // k = 2..6
}

TEST(Effects, ChangesOfOneKindMakeOneCategory) {
  BehaviourTrials t = lift_trials(100, 2);
  for (auto& trial : t.trials) {
    trial.change[0] = trial.change[1];  // nothing came up, only noise
    trial.atoms_after = trial.atoms_before;
  }
  EXPECT_EQ(categorise(t).count, 1);
  for (auto& trial : t.trials) trial.change = {0, 0};
  const EffectCategories still = categorise(t);
  EXPECT_EQ(still.count, 1);
  EXPECT_TRUE(still.effects[0].add.empty() && still.effects[0].remove.empty());
}

TEST(Effects, ThreeGroupsOfChangeMakeThree) {
  BehaviourTrials t = lift_trials(300, 3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  for (std::size_t i = 0; i < t.trials.size(); ++i)
    t.trials[i].change = {0.3 * static_cast<double>(i % 3) + noise(rng), 0.5 * static_cast<double>(i % 3 == 1) + noise(rng)};
  EXPECT_EQ(categorise(t).count, 3);
}

TEST(Effects, TheTreesRulesHoldOnTheTrialsAndPredictHeldOutOnes) {
  const BehaviourTrials t = lift_trials(300, 4);
  const LearnedBehaviour l = learn_behaviour(t);
  EXPECT_GE(l.held_out_accuracy, 0.9);
  EXPECT_GT(l.held_out_trials, 50);
  EXPECT_GE(l.rules.size(), 2U);
  EXPECT_EQ(l.always_before, (std::vector<Atom>{{"hand-free", {}}, {"robot-at", {"?t"}}}));
  int right = 0, counted = 0;
  for (std::size_t i = 0; i < t.trials.size(); ++i) {
    // Exactly one rule meets each trial, and the rules' counts are the trials'.
    int meeting = 0;
    for (const auto& r : l.rules) {
      bool all = true;
      for (const auto& c : r.conditions) {
        const double v = t.trials[i].before[c.feature];
        all = all && (c.at_most ? v <= c.value : v > c.value);
      }
      meeting += all;
    }
    EXPECT_EQ(meeting, 1) << "trial " << i;
    right += rule_for(l, t.trials[i].before, t.trials[i].atoms_before).category ==
             l.categories.of_trial[i];
  }
  for (const auto& r : l.rules)
    for (const auto& [category, count] : r.trials_per_category) counted += count;
  EXPECT_EQ(counted, 300);
  EXPECT_GE(right, 285);
}

TEST(Effects, AnAtomThatDecidesTheEffectBecomesAPrecondition) {
  const BehaviourTrials t = put_down_trials(200, 5);
  const LearnedBehaviour l = learn_behaviour(t);
  EXPECT_EQ(l.categories.count, 2);
  EXPECT_EQ(l.input_atoms, (std::vector<Atom>{{"loaded", {"?s"}}}));
  const LearnedDomain d = learned_domain(vocabulary(), {t}, {l});
  // One operator needs the switch loaded and presses it surely; one does not, and presses it
  // about half the time (the stiff switches the robot cannot tell apart).
  bool sure = false, unsure = false;
  for (const auto& op : d.domain.operators) {
    const bool needs_load = std::count(op.requires_true.begin(), op.requires_true.end(), Atom{"loaded", {"?s"}}) > 0;
    const bool forbids_load = std::count(op.requires_false.begin(), op.requires_false.end(), Atom{"loaded", {"?s"}}) > 0;
    ASSERT_NE(needs_load, forbids_load) << op.name;
    if (needs_load) {
      sure = op.outcomes.size() == 1 && op.outcomes[0].probability == 1.0;
      EXPECT_NE(std::find(op.outcomes[0].add.begin(), op.outcomes[0].add.end(), Atom{"pressed", {"?s"}}),
                op.outcomes[0].add.end());
    } else {
      ASSERT_EQ(op.outcomes.size(), 2U);
      unsure = op.outcomes[1].probability > 0.3;
    }
  }
  EXPECT_TRUE(sure);
  EXPECT_TRUE(unsure);
}

/// A room with cans of these hues (width 6 cm) at their places, a switch and a door.
struct Room {
  pddl::Problem problem;
  std::vector<PerceivedObject> objects;
};
Room room_with_cans(const LearnedDomain& d, const std::vector<double>& hues) {
  Room r;
  r.problem.name = "cans";
  r.problem.domain = d.domain.name;
  r.problem.objects = {{"start", "place"}, {"switch-1", "switch"}, {"door-1", "door"}};
  r.problem.init = {{"robot-at", {"start"}}, {"hand-free", {}}, {"opens", {"switch-1", "door-1"}}};
  for (std::size_t i = 0; i < hues.size(); ++i) {
    const std::string name = "can-" + std::to_string(i + 1);
    r.problem.objects.push_back({name, "thing"});
    r.objects.push_back({name, "thing", {{"hue", hues[i]}, {"width_m", 0.06}}});
  }
  for (auto& a : threshold_atoms(d.domain, d.thresholds, r.objects)) r.problem.init.push_back(a);
  r.problem.goal_true = {{"holding", {"can-3"}}};
  return r;
}

TEST(Effects, TheLearnedDomainPlansTheSameFromItsFilesAsInMemory) {
  const BehaviourTrials go = go_trials(50, 5), lift = lift_trials(300, 6),
                        put = put_down_trials(200, 7);
  const std::vector<BehaviourTrials> all{go, lift, put};
  const std::vector<LearnedBehaviour> learned{learn_behaviour(go), learn_behaviour(lift),
                                              learn_behaviour(put)};
  const LearnedDomain d = learned_domain(vocabulary(), all, learned);
  ASSERT_FALSE(d.thresholds.empty());
  // can-3 is blue (240 degrees): nothing the robot learned lifts it; can-2 (30 degrees) it lifts.
  Room room = room_with_cans(d, {300, 30, 240});
  EXPECT_FALSE(plan(d.domain, room.problem).plan);
  room.problem.goal_true = {{"holding", {"can-2"}}};
  const PlanResult in_memory = plan(d.domain, room.problem);
  ASSERT_TRUE(in_memory.plan) << in_memory.reason;
  ASSERT_EQ(in_memory.plan->steps.size(), 1U + 1U);  // go, lift
  EXPECT_EQ(in_memory.plan->steps[1].arguments, (std::vector<std::string>{"can-2"}));
  // Written and read back: the same domain, problem and plan.
  const pddl::Domain read = pddl::read_domain(pddl::write(d.domain, pddl::Dialect::Probabilistic), "effects.ppddl");
  const pddl::Problem problem = pddl::read_problem(pddl::write(room.problem), "scene.pddl", read);
  const PlanResult from_files = plan(read, problem);
  ASSERT_TRUE(from_files.plan);
  ASSERT_EQ(from_files.plan->steps.size(), in_memory.plan->steps.size());
  for (std::size_t i = 0; i < in_memory.plan->steps.size(); ++i) {
    EXPECT_EQ(from_files.plan->steps[i].text(), in_memory.plan->steps[i].text());
    EXPECT_EQ(from_files.plan->steps[i].probability, in_memory.plan->steps[i].probability);
  }
  for (std::size_t i = 0; i < read.operators.size(); ++i) {
    EXPECT_EQ(read.operators[i].outcomes, d.domain.operators[i].outcomes);
    EXPECT_EQ(read.operators[i].requires_true, d.domain.operators[i].requires_true);
    EXPECT_EQ(read.operators[i].requires_false, d.domain.operators[i].requires_false);
  }
}

TEST(Effects, TrialsReadBackFromTheirTextAsWritten) {
  const std::vector<BehaviourTrials> all{go_trials(5, 1), lift_trials(20, 2), put_down_trials(10, 3)};
  const auto back = read_effect_trials(write_effect_trials(all), "trials.csv");
  ASSERT_EQ(back.size(), 3U);
  for (std::size_t b = 0; b < all.size(); ++b) {
    EXPECT_EQ(back[b].behaviour, all[b].behaviour);
    EXPECT_EQ(back[b].parameters, all[b].parameters);
    ASSERT_EQ(back[b].trials.size(), all[b].trials.size());
    for (std::size_t i = 0; i < all[b].trials.size(); ++i) {
      EXPECT_EQ(back[b].trials[i].before, all[b].trials[i].before);  // exactly
      EXPECT_EQ(back[b].trials[i].change, all[b].trials[i].change);
      EXPECT_EQ(back[b].trials[i].atoms_before, all[b].trials[i].atoms_before);
      EXPECT_EQ(back[b].trials[i].atoms_after, all[b].trials[i].atoms_after);
      EXPECT_EQ(back[b].trials[i].label, all[b].trials[i].label);
    }
  }
  const auto bad = [](const std::string& text, const std::string& what) {
    try {
      read_effect_trials(text, "t.csv");
      ADD_FAILURE() << text;
    } catch (const pddl::PddlError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string header = "behaviour,parameters,seed,label,features,changes,atoms_before,atoms_after\n";
  bad("a,b\n", "t.csv:1: not a file of effect trials");
  bad(header + "lift,?t - thing,1,x,hue:?t=nan,h@0.1=0,,\n", "t.csv:2: features: 'nan' is no finite number");
  bad(header + "lift,?t - thing,1,x,hue:?t=1,h@0.1=0,(holding ?t,\n", "t.csv:2: atoms_before");
  bad(header + "lift,?t - thing,1,x,hue:?t=1\n", "t.csv:2: 8 fields expected, found 5");
  bad(header + "lift,?t - thing,1,x,hue:?t=1,h@0.1=0,,\nlift,?t - thing,2,x,fill:?t=1,h@0.1=0,,\n",
      "t.csv:3: its features or changes differ");
}

TEST(Effects, ThresholdsReadBackFromTheirFile) {
  const macsim::test::TempDir dir("effects_thresholds_");
  const std::vector<Threshold> t{{"hue-le-214p5", "hue", "thing", 214.51234567890123},
                                 {"width_m-le-0p08", "width_m", "thing", 0.08}};
  save_thresholds(t, dir.path() + "/thresholds.yml");
  const auto back = load_thresholds(dir.path() + "/thresholds.yml");
  ASSERT_EQ(back.size(), 2U);
  EXPECT_EQ(back[0].predicate, t[0].predicate);
  EXPECT_EQ(back[0].value, t[0].value);
  EXPECT_EQ(back[1].type, "thing");
  EXPECT_THROW(load_thresholds(dir.path() + "/none.yml"), pddl::PddlError);
}

/// The committed rows (tests/affordances/effect_trials.csv), the behaviours learned from them and
/// their domain, as learn_effects --from-trials makes them.
struct Committed {
  std::vector<BehaviourTrials> trials;
  std::vector<LearnedBehaviour> learned;
  LearnedDomain domain;
};
Committed learned_from_committed_rows() {
  const std::string file = macsim::test::source("tests/affordances/effect_trials.csv");
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  Committed c;
  c.trials = read_effect_trials(text.str(), file);
  for (auto& t : c.trials) keep_typed_atoms(vocabulary(), t);
  for (const auto& t : c.trials) c.learned.push_back(learn_behaviour(t));
  c.domain = learned_domain(vocabulary(), c.trials, c.learned);
  return c;
}

/// The domain learned from the committed rows (learned once per test binary).
const LearnedDomain& learned_domain_of_committed_rows() {
  static const LearnedDomain d = learned_from_committed_rows().domain;
  return d;
}

/// The committed rows of learn_effects (exploration episodes against macsim): the domain learned
/// from them, its rules checked against the rows they were read off.
TEST(Effects, TheDomainLearnedFromTheCommittedRowsHoldsOnThoseRows) {
  const Committed c = learned_from_committed_rows();
  const auto& [trials, learned, d] = c;
  ASSERT_GE(trials.size(), 3U);
  std::size_t op = 0;
  for (std::size_t b = 0; b < trials.size(); ++b) {
    const auto& t = trials[b];
    const auto& l = learned[b];
    // Each trial meets exactly one rule; that rule's operator applies where the trial started
    // (its atoms before, and the thresholds its features meet), and the rule's counts add up.
    int counted = 0;
    for (const auto& r : l.rules)
      for (const auto& [category, count] : r.trials_per_category) counted += count;
    EXPECT_EQ(counted, static_cast<int>(t.trials.size())) << t.behaviour;
    for (const auto& trial : t.trials) {
      std::map<std::string, double> features;
      for (std::size_t f = 0; f < t.features.size(); ++f) features[t.features[f].name] = trial.before[f];
      std::set<Atom> state(trial.atoms_before.begin(), trial.atoms_before.end());
      for (const auto& p : t.parameters)
        for (auto& a : threshold_atoms(d.domain, d.thresholds, {{p.name, p.type, features}}))
          state.insert(a);
      int applicable = 0;
      for (std::size_t r = 0; r < l.rules.size(); ++r) {
        const pddl::Operator& o = d.domain.operators[op + r];
        const bool holds =
            std::all_of(o.requires_true.begin(), o.requires_true.end(), [&](const Atom& a) { return state.count(a) > 0; }) &&
            std::none_of(o.requires_false.begin(), o.requires_false.end(), [&](const Atom& a) { return state.count(a) > 0; });
        applicable += holds;
        if (holds) {
          EXPECT_EQ(&l.rules[r], &rule_for(l, trial.before, trial.atoms_before)) << o.name;
        }
      }
      EXPECT_EQ(applicable, 1) << t.behaviour << " trial " << trial.seed;
    }
    op += l.rules.size();
  }
  EXPECT_EQ(op, d.domain.operators.size());
  // Written as files and read back: the same operators.
  const pddl::Domain read =
      pddl::read_domain(pddl::write(d.domain, pddl::Dialect::Probabilistic), "effects.ppddl");
  ASSERT_EQ(read.operators.size(), d.domain.operators.size());
  for (std::size_t i = 0; i < read.operators.size(); ++i) {
    EXPECT_EQ(read.operators[i].outcomes, d.domain.operators[i].outcomes) << read.operators[i].name;
    EXPECT_EQ(read.operators[i].requires_true, d.domain.operators[i].requires_true);
    EXPECT_EQ(read.operators[i].requires_false, d.domain.operators[i].requires_false);
  }
}

TEST(Effects, TheCommittedRowsTeachThatASecondThingPressesASwitchOneMayLeaveUp) {
  // The trial room's switch is softer than one can in some layouts, stiffer in the others: the
  // learned put-down splits on whether something already lies on the platform.
  const LearnedDomain d = learned_domain_of_committed_rows();
  const Atom loaded{"loaded", {"?s"}}, pressed{"pressed", {"?s"}};
  auto chance_pressed = [&](const pddl::Operator& o) {
    double p = 0;
    for (const auto& outcome : o.outcomes)
      if (std::count(outcome.add.begin(), outcome.add.end(), pressed)) p += outcome.probability;
    return p;
  };
  int on_loaded = 0, on_empty = 0;
  for (const auto& o : d.domain.operators) {
    if (o.name.rfind("put-down", 0) != 0) continue;
    if (std::count(o.requires_true.begin(), o.requires_true.end(), loaded)) {
      ++on_loaded;
      EXPECT_GT(chance_pressed(o), 0.8) << o.name;
    } else {
      ASSERT_TRUE(std::count(o.requires_false.begin(), o.requires_false.end(), loaded)) << o.name;
      ++on_empty;
      EXPECT_GT(chance_pressed(o), 0.1) << o.name;
      EXPECT_LT(chance_pressed(o), 0.6) << o.name;
    }
  }
  EXPECT_EQ(on_loaded, 1);
  EXPECT_EQ(on_empty, 1);
}

TEST(Effects, TheCommittedRowsTeachThatAPushedBoxMayPressAFlushSwitchAndAPushedCanDoesNot) {
  // The push trials (the push-to-switch room: a plate flush with the floor, boxes and cans) split
  // on what the cameras call a box: a box pushed toward the plate presses it often enough to
  // plan on, a can never does.
  const LearnedDomain d = learned_domain_of_committed_rows();
  const Atom box{"box", {"?t"}}, loaded{"loaded", {"?s"}}, pressed{"pressed", {"?s"}}, flush{"flush", {"?s"}};
  int of_box = 0, of_other = 0;
  for (const auto& o : d.domain.operators) {
    if (o.name.rfind("push", 0) != 0) continue;
    EXPECT_TRUE(std::count(o.requires_true.begin(), o.requires_true.end(), flush)) << o.name;
    if (std::count(o.requires_true.begin(), o.requires_true.end(), loaded)) continue;  // pressed already
    double p = 0;
    for (const auto& outcome : o.outcomes)
      if (std::count(outcome.add.begin(), outcome.add.end(), pressed)) p += outcome.probability;
    if (std::count(o.requires_true.begin(), o.requires_true.end(), box)) {
      ++of_box;
      EXPECT_GE(p, PlanLimits{}.min_probability) << o.name;
    } else {
      ++of_other;
      EXPECT_LT(p, 0.1) << o.name;
    }
  }
  EXPECT_EQ(of_box, 1);
  EXPECT_EQ(of_other, 1);
}

TEST(Effects, ThresholdPredicatesAreNamesPddlReads) {
  EXPECT_EQ(threshold_predicate("hue", 214.5), "hue-le-214p5");
  EXPECT_EQ(threshold_predicate("laser_slope", -0.25), "laser_slope-le-m0p25");
  EXPECT_EQ(threshold_predicate("Width M", 1e-5), "width_m-le-1em05");
}

TEST(Effects, TrialsWhoseColumnsDoNotMatchOrAreNotFiniteAreRefused) {
  BehaviourTrials t = lift_trials(10, 8);
  t.trials[3].before.pop_back();
  EXPECT_THROW(categorise(t), std::invalid_argument);
  t = lift_trials(10, 8);
  t.trials[4].change[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(learn_behaviour(t), std::invalid_argument);
}

}  // namespace
}  // namespace macsim::affordances
