// Grounding and search: operators instantiated on objects of their parameters' types (pruned by
// the static predicates as parameters are bound), one per outcome worth counting on, reduced to
// those that can matter to the goal, then A* over states as bit sets, h_max as the heuristic
// (admissible: the plan is shortest).
#include "macsim/affordances/planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <set>
#include <unordered_map>

namespace macsim::affordances {
namespace {

using pddl::Atom;
using pddl::Domain;
using pddl::Operator;
using pddl::Outcome;
using pddl::Problem;

/// A ground operator over atom indices.
struct Ground {
  const Operator* op = nullptr;
  std::vector<std::string> arguments;
  std::vector<int> requires_true, requires_false, add, remove;
  double probability = 1;
  Outcome outcome;  // grounded
};

using Bits = std::vector<std::uint64_t>;

bool test(const Bits& b, int i) { return (b[i >> 6] >> (i & 63)) & 1U; }
void set(Bits& b, int i) { b[i >> 6] |= std::uint64_t{1} << (i & 63); }
void clear(Bits& b, int i) { b[i >> 6] &= ~(std::uint64_t{1} << (i & 63)); }

struct BitsHash {
  std::size_t operator()(const Bits& b) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (const auto w : b) {
      h ^= w + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
      h *= 0xff51afd7ed558ccdULL;
    }
    return static_cast<std::size_t>(h ^ (h >> 33));
  }
};

/// The operators grounded on the problem's objects, the atoms they touch numbered.
class Grounding {
 public:
  Grounding(const Domain& domain, const Problem& problem, double min_probability)
      : domain_(domain), min_probability_(min_probability) {
    for (const auto& o : problem.objects) objects_.push_back(&o);
    for (const auto& op : domain.operators)
      for (const auto& out : op.outcomes) {
        for (const auto& a : out.add) dynamic_.insert(a.predicate);
        for (const auto& a : out.remove) dynamic_.insert(a.predicate);
      }
    for (const auto& a : problem.init)
      if (!dynamic_.count(a.predicate)) static_facts_.insert(a);
    for (const auto& a : problem.init)
      if (dynamic_.count(a.predicate)) init_.push_back(index(a));
    for (const auto& op : domain.operators) ground(op);
  }

  int index(const Atom& a) {
    const auto [it, added] = atoms_.emplace(a, static_cast<int>(names_.size()));
    if (added) names_.push_back(a);
    return it->second;
  }
  std::optional<int> find(const Atom& a) const {
    const auto it = atoms_.find(a);
    return it == atoms_.end() ? std::nullopt : std::optional<int>(it->second);
  }
  bool is_static(const std::string& predicate) const { return !dynamic_.count(predicate); }
  bool static_holds(const Atom& a) const { return static_facts_.count(a) > 0; }

  std::vector<Ground> operators;
  std::vector<int> init_;
  std::vector<Atom> names_;

 private:
  /// The outcomes planned on: each that changes something and is at least `min_probability`
  /// likely (all-outcomes determinization: a step counts on one of them, its probability beside).
  std::vector<const Outcome*> plannable(const Operator& op) const {
    std::vector<const Outcome*> out;
    for (const auto& o : op.outcomes)
      if ((!o.add.empty() || !o.remove.empty()) && o.probability >= min_probability_ - 1e-12)
        out.push_back(&o);
    return out;
  }

  void ground(const Operator& op) {
    const auto outcomes = plannable(op);
    if (outcomes.empty()) return;
    // Candidates per parameter, and the static preconditions checkable once parameter k is bound.
    const std::size_t n = op.parameters.size();
    std::vector<std::vector<const pddl::Typed*>> candidates(n);
    for (std::size_t k = 0; k < n; ++k)
      for (const auto* o : objects_)
        if (pddl::is_a(domain_, o->type, op.parameters[k].type)) candidates[k].push_back(o);
    std::map<std::string, std::size_t> position;
    for (std::size_t k = 0; k < n; ++k) position[op.parameters[k].name] = k;
    struct StaticCheck {
      const Atom* atom;
      bool positive;
    };
    std::vector<std::vector<StaticCheck>> checks(n + 1);
    const auto last_bound = [&](const Atom& a) {
      std::size_t last = 0;
      for (const auto& arg : a.arguments) last = std::max(last, position.at(arg) + 1);
      return last;
    };
    for (const auto& a : op.requires_true)
      if (is_static(a.predicate)) checks[last_bound(a)].push_back({&a, true});
    for (const auto& a : op.requires_false)
      if (is_static(a.predicate)) checks[last_bound(a)].push_back({&a, false});
    std::vector<std::string> binding(n);
    const auto bind = [&](const Atom& a) {
      Atom g{a.predicate, {}};
      for (const auto& arg : a.arguments) g.arguments.push_back(binding[position.at(arg)]);
      return g;
    };
    const auto checks_hold = [&](std::size_t level) {
      for (const auto& c : checks[level])
        if (static_holds(bind(*c.atom)) != c.positive) return false;
      return true;
    };
    if (!checks_hold(0)) return;
    std::function<void(std::size_t)> descend = [&](std::size_t k) {
      if (k == n) {
        for (const Outcome* o : outcomes) emit(op, binding, *o, o->probability, bind);
        return;
      }
      for (const auto* o : candidates[k]) {
        binding[k] = o->name;
        if (checks_hold(k + 1)) descend(k + 1);
      }
    };
    descend(0);
  }

  template <typename Bind>
  void emit(const Operator& op, const std::vector<std::string>& binding, const Outcome& outcome,
            double probability, Bind bind) {
    Ground g;
    g.op = &op;
    g.arguments = binding;
    g.probability = probability;
    for (const auto& a : op.requires_true)
      if (!is_static(a.predicate)) g.requires_true.push_back(index(bind(a)));
    for (const auto& a : op.requires_false)
      if (!is_static(a.predicate)) g.requires_false.push_back(index(bind(a)));
    for (const auto& a : outcome.add) {
      g.outcome.add.push_back(bind(a));
      g.add.push_back(index(g.outcome.add.back()));
    }
    for (const auto& a : outcome.remove) {
      g.outcome.remove.push_back(bind(a));
      g.remove.push_back(index(g.outcome.remove.back()));
    }
    g.outcome.probability = probability;
    operators.push_back(std::move(g));
  }

  const Domain& domain_;
  double min_probability_;
  std::vector<const pddl::Typed*> objects_;
  std::set<std::string> dynamic_;
  std::set<Atom> static_facts_;
  std::map<Atom, int> atoms_;
};

constexpr int kUnreached = std::numeric_limits<int>::max();

/// h_max: per atom the most steps any one of its preconditions needs in the relaxed problem.
class HMax {
 public:
  HMax(const std::vector<Ground>& ops, int atoms) : ops_(ops), cost_(atoms) {}

  /// The relaxed steps to the goal from `state`, kUnreached when no relaxed plan exists; the
  /// atoms' costs are left in cost() for the caller.
  int operator()(const Bits& state, const std::vector<int>& goal) {
    const int atoms = static_cast<int>(cost_.size());
    for (int i = 0; i < atoms; ++i) cost_[i] = test(state, i) ? 0 : kUnreached;
    for (bool changed = true; changed;) {
      changed = false;
      for (const auto& g : ops_) {
        int c = 0;
        for (const int p : g.requires_true) c = std::max(c, cost_[p]);
        if (c == kUnreached) continue;
        for (const int a : g.add)
          if (c + 1 < cost_[a]) {
            cost_[a] = c + 1;
            changed = true;
          }
      }
    }
    int h = 0;
    for (const int a : goal) h = std::max(h, cost_[a]);
    return h;
  }
  const std::vector<int>& cost() const { return cost_; }

 private:
  const std::vector<Ground>& ops_;
  std::vector<int> cost_;
};

/// Keeps the operators that can matter to the goal: those that change an atom the goal, or a
/// kept operator's precondition, names (backwards to a fixed point).
std::vector<Ground> relevant(std::vector<Ground> ops, const std::vector<int>& goal_atoms,
                             int atoms) {
  std::vector<char> atom_relevant(atoms, 0), op_relevant(ops.size(), 0);
  for (const int a : goal_atoms) atom_relevant[a] = 1;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < ops.size(); ++i) {
      if (op_relevant[i]) continue;
      const auto& g = ops[i];
      const bool touches =
          std::any_of(g.add.begin(), g.add.end(), [&](int a) { return atom_relevant[a]; }) ||
          std::any_of(g.remove.begin(), g.remove.end(), [&](int a) { return atom_relevant[a]; });
      if (!touches) continue;
      op_relevant[i] = 1;
      changed = true;
      for (const int p : g.requires_true) atom_relevant[p] = 1;
      for (const int p : g.requires_false) atom_relevant[p] = 1;
    }
  }
  std::vector<Ground> kept;
  for (std::size_t i = 0; i < ops.size(); ++i)
    if (op_relevant[i]) kept.push_back(std::move(ops[i]));
  return kept;
}

/// Keeps the steps that can help: one that adds an atom some step or the goal needs true, or
/// removes one some step or the goal needs false. A step that only disables others (a lift that
/// leaves the thing tried and nothing else) is never needed: a plan without it is a plan still.
std::vector<Ground> useful(std::vector<Ground> ops, const Problem& problem, Grounding& grounding,
                           int atoms) {
  std::vector<char> needed_true(atoms, 0), needed_false(atoms, 0);
  for (const auto& g : ops) {
    for (const int a : g.requires_true) needed_true[a] = 1;
    for (const int a : g.requires_false) needed_false[a] = 1;
  }
  for (const auto& a : problem.goal_true)
    if (const auto i = grounding.find(a)) needed_true[*i] = 1;
  for (const auto& a : problem.goal_false)
    if (const auto i = grounding.find(a)) needed_false[*i] = 1;
  std::erase_if(ops, [&](const Ground& g) {
    return std::none_of(g.add.begin(), g.add.end(), [&](int a) { return needed_true[a] != 0; }) &&
           std::none_of(g.remove.begin(), g.remove.end(), [&](int a) { return needed_false[a] != 0; });
  });
  return ops;
}

struct SearchNode {
  Bits state;
  int parent = -1;
  int via = -1;  // ground operator
  int steps = 0;
  double surprise = 0;  // -log of the plan's probability so far
};

}  // namespace

std::string PlanStep::text() const { return pddl::text(Atom{operator_name, arguments}); }

PlanResult plan(const Domain& domain, const Problem& problem, const PlanLimits& limits) {
  const auto started = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  PlanResult result;
  Grounding grounding(domain, problem, limits.min_probability);
  // The goal over numbered atoms; atoms no operator touches and the start lacks are false.
  std::vector<int> goal_true, goal_false;
  std::vector<std::string> never;
  for (const auto& a : problem.goal_true) {
    if (grounding.is_static(a.predicate)) {
      if (!grounding.static_holds(a)) never.push_back(pddl::text(a) + " (nothing makes it true)");
      continue;
    }
    goal_true.push_back(grounding.index(a));
  }
  for (const auto& a : problem.goal_false) {
    if (grounding.is_static(a.predicate)) {
      if (grounding.static_holds(a)) never.push_back("(not " + pddl::text(a) + ") (nothing makes it false)");
      continue;
    }
    goal_false.push_back(grounding.index(a));
  }
  const int atoms = static_cast<int>(grounding.names_.size());
  const std::size_t words = static_cast<std::size_t>(atoms + 63) / 64;
  Bits start(words, 0);
  for (const int a : grounding.init_) set(start, a);
  std::vector<int> goal_atoms = goal_true;
  goal_atoms.insert(goal_atoms.end(), goal_false.begin(), goal_false.end());
  std::vector<Ground> ops =
      useful(relevant(std::move(grounding.operators), goal_atoms, atoms), problem, grounding, atoms);
  result.ground_operators = ops.size();
  if (!never.empty()) {
    result.reason = "the goal cannot be reached: ";
    for (std::size_t i = 0; i < never.size(); ++i) result.reason += (i ? ", " : "") + never[i];
    result.seconds = elapsed();
    return result;
  }
  HMax hmax(ops, atoms);
  const auto satisfied = [&](const Bits& s) {
    for (const int a : goal_true)
      if (!test(s, a)) return false;
    for (const int a : goal_false)
      if (test(s, a)) return false;
    return true;
  };
  if (hmax(start, goal_true) == kUnreached) {
    result.reason = "the goal cannot be reached: no sequence of steps makes ";
    bool first = true;
    for (const int a : goal_true)
      if (hmax.cost()[a] == kUnreached) {
        result.reason += (first ? "" : ", ") + pddl::text(grounding.names_[a]);
        first = false;
      }
    result.reason += " true";
    result.seconds = elapsed();
    return result;
  }
  // A*: fewest steps first (f), then the deepest (a layer of equal f is searched depth first, so
  // that it ends soon), then the likeliest.
  struct Open {
    int f;
    double surprise;
    int steps;
    int node;
    bool operator>(const Open& o) const {
      if (f != o.f) return f > o.f;
      if (steps != o.steps) return steps < o.steps;
      if (surprise != o.surprise) return surprise > o.surprise;
      return node > o.node;
    }
  };
  std::vector<SearchNode> nodes;
  std::unordered_map<Bits, int, BitsHash> seen;
  std::priority_queue<Open, std::vector<Open>, std::greater<>> open;
  nodes.push_back(SearchNode{start, -1, -1, 0, 0});
  seen.emplace(start, 0);
  open.push({hmax(start, goal_true), 0, 0, 0});
  result.generated = 1;
  std::vector<char> closed(1, 0);
  while (!open.empty()) {
    const Open top = open.top();
    open.pop();
    if (closed[top.node]) continue;
    closed[top.node] = 1;
    const SearchNode current = nodes[top.node];
    if (satisfied(current.state)) {
      Plan p;
      for (int at = top.node; nodes[at].parent >= 0; at = nodes[at].parent) {
        const Ground& g = ops[nodes[at].via];
        p.steps.push_back(PlanStep{g.op->name, g.arguments, g.probability, g.outcome});
        p.probability *= g.probability;
      }
      std::reverse(p.steps.begin(), p.steps.end());
      result.plan = std::move(p);
      result.seconds = elapsed();
      return result;
    }
    ++result.expanded;
    for (std::size_t i = 0; i < ops.size(); ++i) {
      const Ground& g = ops[i];
      if (!std::all_of(g.requires_true.begin(), g.requires_true.end(),
                       [&](int a) { return test(current.state, a); }) ||
          std::any_of(g.requires_false.begin(), g.requires_false.end(),
                      [&](int a) { return test(current.state, a); }))
        continue;
      Bits next = current.state;
      for (const int a : g.remove) clear(next, a);
      for (const int a : g.add) set(next, a);
      if (next == current.state) continue;
      const int steps = current.steps + 1;
      const double surprise = current.surprise - std::log(std::max(g.probability, 1e-300));
      const auto it = seen.find(next);
      int index;
      if (it != seen.end()) {
        SearchNode& known = nodes[it->second];
        if (known.steps < steps || (known.steps == steps && known.surprise <= surprise)) continue;
        known.parent = top.node;
        known.via = static_cast<int>(i);
        known.steps = steps;
        known.surprise = surprise;
        closed[it->second] = 0;
        index = it->second;
      } else {
        index = static_cast<int>(nodes.size());
        nodes.push_back(SearchNode{next, top.node, static_cast<int>(i), steps, surprise});
        closed.push_back(0);
        seen.emplace(std::move(next), index);
      }
      ++result.generated;
      const int h = hmax(nodes[index].state, goal_true);
      if (h == kUnreached) continue;
      open.push({steps + h, surprise, steps, index});
    }
    if (result.generated >= limits.max_states || elapsed() > limits.max_seconds) {
      result.limit_reached = true;
      result.reason = "no plan found within the search's limit (" +
                      std::to_string(result.generated) + " states, " +
                      std::to_string(elapsed()).substr(0, 5) + " s)";
      result.seconds = elapsed();
      return result;
    }
  }
  result.reason = "the goal cannot be reached: every state reachable from the start (" +
                  std::to_string(nodes.size()) + ") was searched";
  result.seconds = elapsed();
  return result;
}

std::vector<PlanStep> applicable(const Domain& domain, const Problem& problem) {
  Grounding grounding(domain, problem, 0);
  Bits state((grounding.names_.size() + 63) / 64, 0);
  for (const int a : grounding.init_) set(state, a);
  const auto holds = [&](int a) { return a < static_cast<int>(grounding.names_.size()) && test(state, a); };
  std::vector<PlanStep> steps;
  std::map<std::pair<const Operator*, std::vector<std::string>>, std::size_t> seen;
  for (const auto& g : grounding.operators) {
    if (!std::all_of(g.requires_true.begin(), g.requires_true.end(), holds) ||
        std::any_of(g.requires_false.begin(), g.requires_false.end(), holds))
      continue;
    // A step that would leave the state as it is (a go from a place to itself) is no choice.
    const bool changes = std::any_of(g.add.begin(), g.add.end(), [&](int a) { return !holds(a); }) ||
                         std::any_of(g.remove.begin(), g.remove.end(), [&](int a) {
                           return holds(a) && std::find(g.add.begin(), g.add.end(), a) == g.add.end();
                         });
    if (!changes) continue;
    const auto [it, fresh] = seen.try_emplace({g.op, g.arguments}, steps.size());
    if (!fresh && steps[it->second].probability >= g.probability) continue;
    PlanStep step{g.op->name, g.arguments, g.probability, g.outcome};
    if (fresh)
      steps.push_back(std::move(step));
    else
      steps[it->second] = std::move(step);
  }
  return steps;
}

std::vector<Atom> state_after(const std::vector<Atom>& state, const PlanStep& step) {
  std::set<Atom> s(state.begin(), state.end());
  for (const auto& a : step.expected.remove) s.erase(a);
  for (const auto& a : step.expected.add) s.insert(a);
  return {s.begin(), s.end()};
}

bool satisfies(const std::vector<Atom>& state, const Problem& problem) {
  const std::set<Atom> s(state.begin(), state.end());
  return std::all_of(problem.goal_true.begin(), problem.goal_true.end(),
                     [&](const Atom& a) { return s.count(a) > 0; }) &&
         std::none_of(problem.goal_false.begin(), problem.goal_false.end(),
                      [&](const Atom& a) { return s.count(a) > 0; });
}

}  // namespace macsim::affordances
