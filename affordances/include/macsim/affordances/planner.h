// Plans over a PDDL domain (pddl.h): the operators grounded on the problem's objects, a step for
// each outcome worth counting on (all-outcomes determinization: a lift that comes up half the
// time may be planned on, its probability beside), and an A* search (h_max) for the fewest steps
// and, of those, the likeliest plan. A goal no plan reaches is reported with the reason.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "macsim/affordances/pddl.h"

namespace macsim::affordances {

/// One step of a plan: a ground operator and the outcome the plan counts on.
struct PlanStep {
  std::string operator_name;
  std::vector<std::string> arguments;
  double probability = 1;  ///< of the outcome counted on
  pddl::Outcome expected;  ///< that outcome, grounded on the arguments
  /// "(operator arg ...)".
  std::string text() const;
};

/// A sequence of steps that reaches the goal if every step has its most likely outcome.
struct Plan {
  std::vector<PlanStep> steps;
  double probability = 1;  ///< of every step's outcome together
};

/// Bounds of one search.
struct PlanLimits {
  std::size_t max_states = 2'000'000;  ///< states generated
  double max_seconds = 10;             ///< wall time
  /// Outcomes less likely than this are not counted on (nor any that changes nothing).
  double min_probability = 0.25;
};

/// What a search found: a plan, or why there is none.
struct PlanResult {
  std::optional<Plan> plan;
  /// No plan: the goal atoms that no sequence of steps can make true, or that every reachable
  /// state was searched, or that a limit stopped the search.
  std::string reason;
  bool limit_reached = false;  ///< no plan found within PlanLimits (one may exist)
  std::size_t ground_operators = 0;  ///< after dropping those that cannot matter to the goal
  std::size_t expanded = 0, generated = 0;
  double seconds = 0;  ///< grounding and search
};

/// Plans for `problem` over `domain` (the problem checked against the domain, as
/// pddl::read_problem does).
PlanResult plan(const pddl::Domain& domain, const pddl::Problem& problem,
                const PlanLimits& limits = {});

/// The steps whose preconditions hold in `problem`'s initial state and that change it, one per
/// ground operator (its most likely outcome expected), in the domain's order: what a policy that
/// does not plan may choose from.
std::vector<PlanStep> applicable(const pddl::Domain& domain, const pddl::Problem& problem);

/// The atoms that hold after `step` (its expected outcome) where `state` held.
std::vector<pddl::Atom> state_after(const std::vector<pddl::Atom>& state, const PlanStep& step);
/// True when every atom of goal_true holds in `state` and none of goal_false.
bool satisfies(const std::vector<pddl::Atom>& state, const pddl::Problem& problem);

}  // namespace macsim::affordances
