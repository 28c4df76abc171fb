// Planning domains and problems as PDDL text: STRIPS with types and negative preconditions, and
// PPDDL's probabilistic effects. Written for people and for any planner; read back checked
// against the domain, a fault named by file and line. No planner here: planner.h plans on these.
#pragma once

#include <compare>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace macsim::affordances::pddl {

/// A PDDL text that cannot be read: the message starts "FILE:LINE: ".
class PddlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A name and its type: a parameter (`?t - thing`), an object (`can_1 - thing`) or a type and
/// its parent (`can - thing`). Names are lower case, as PDDL compares them.
struct Typed {
  std::string name;
  std::string type = "object";
  auto operator<=>(const Typed&) const = default;
};

/// A predicate and its arguments: parameters (`?t`) in a domain, objects in a problem.
struct Atom {
  std::string predicate;
  std::vector<std::string> arguments;
  auto operator<=>(const Atom&) const = default;
};

/// A predicate as the domain declares it.
struct PredicateDeclaration {
  std::string name;
  std::vector<Typed> parameters;
  auto operator<=>(const PredicateDeclaration&) const = default;
};

/// One outcome of an operator: what it makes true and false, and how likely it is.
struct Outcome {
  double probability = 1;
  std::vector<Atom> add, remove;
  auto operator<=>(const Outcome&) const = default;
};

/// An operator: its parameters, what must hold (and must not) before, its outcomes (the most
/// likely first; the probabilities add up to 1 at most, the rest is "nothing changes").
struct Operator {
  std::string name;
  std::vector<Typed> parameters;
  std::vector<Atom> requires_true, requires_false;
  std::vector<Outcome> outcomes;
  std::string note;  ///< written as comment lines above the operator (where it was learned from)
  auto operator<=>(const Operator&) const = default;
};

/// A domain: types (each with its parent), predicates and operators.
struct Domain {
  std::string name;
  std::vector<Typed> types;
  std::vector<PredicateDeclaration> predicates;
  std::vector<Operator> operators;
  std::string note;  ///< written as comment lines at the top
  auto operator<=>(const Domain&) const = default;
};

/// A problem: the objects, what holds at the start, and the goal (atoms that must hold, and
/// atoms that must not).
struct Problem {
  std::string name;
  std::string domain;
  std::vector<Typed> objects;
  std::vector<Atom> init;
  std::vector<Atom> goal_true, goal_false;
  std::string note;  ///< written as comment lines at the top
  auto operator<=>(const Problem&) const = default;
};

/// STRIPS: each operator's most likely outcome, its probability in a comment beside it.
/// Probabilistic: PPDDL, every outcome under `probabilistic`.
enum class Dialect { Strips, Probabilistic };

/// The domain as PDDL text (lower case, one operator a block, notes as comments).
std::string write(const Domain& domain, Dialect dialect);
/// The problem as PDDL text.
std::string write(const Problem& problem);

/// Reads a domain in either dialect (STRIPS effects are one outcome of probability 1); checks
/// that every atom names a declared predicate with its arity and typed parameters of its
/// operator. Throws PddlError naming `file` and the line.
Domain read_domain(std::string_view text, const std::string& file);
/// Reads a problem of `domain`: its objects of declared types, atoms of declared predicates on
/// declared objects. Throws PddlError naming `file` and the line.
Problem read_problem(std::string_view text, const std::string& file, const Domain& domain);

/// The same from files; a file that cannot be read is a PddlError too.
Domain load_domain(const std::string& path);
Problem load_problem(const std::string& path, const Domain& domain);
/// Writes text to path (through a temporary file renamed over it); throws PddlError.
void save_text(const std::string& path, const std::string& text);

/// An atom as PDDL writes it: "(predicate arg ...)".
std::string text(const Atom& atom);
/// Atoms as PDDL writes them, separated by spaces ("" for none).
std::string text(const std::vector<Atom>& atoms);

/// True when `type` is `ancestor` or derives from it in `domain`.
bool is_a(const Domain& domain, const std::string& type, const std::string& ancestor);

}  // namespace macsim::affordances::pddl
