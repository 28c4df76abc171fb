// PDDL text: an s-expression reader that keeps each token's line, the domain and problem readers
// that check names, arities and types against what is declared, and the writers.
#include "macsim/affordances/pddl.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace macsim::affordances::pddl {
namespace {

// ---- s-expressions ------------------------------------------------------------------------

/// A symbol or a list, with the line it starts on.
struct Node {
  bool is_list = false;
  std::string symbol;  // lower case
  std::vector<Node> items;
  int line = 0;
};

/// Reads one s-expression (the whole text), keeping lines; ';' starts a comment to the line's end.
class SexpReader {
 public:
  SexpReader(std::string_view text, const std::string& file) : text_(text), file_(file) {}

  Node read_all() {
    skip_blank();
    if (at_ == text_.size()) fail(line_, "the text is empty; expected '(define ...)'");
    Node root = read_node();
    skip_blank();
    if (at_ != text_.size())
      fail(line_, text_[at_] == ')' ? "a ')' that closes nothing"
                                    : "text after the closing ')' of the definition");
    return root;
  }

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw PddlError(file_ + ":" + std::to_string(line) + ": " + what);
  }

 private:
  void skip_blank() {
    while (at_ < text_.size()) {
      const char c = text_[at_];
      if (c == '\n') {
        ++line_;
        ++at_;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        ++at_;
      } else if (c == ';') {
        while (at_ < text_.size() && text_[at_] != '\n') ++at_;
      } else {
        return;
      }
    }
  }

  Node read_node() {
    skip_blank();
    Node node;
    node.line = line_;
    if (at_ == text_.size()) fail(line_, "the text ends inside a list: a ')' is missing");
    const char c = text_[at_];
    if (c == ')') fail(line_, "a ')' that closes nothing");
    if (c == '(') {
      ++at_;
      node.is_list = true;
      for (;;) {
        skip_blank();
        if (at_ == text_.size())
          fail(node.line, "the list opened here is never closed: a ')' is missing");
        if (text_[at_] == ')') {
          ++at_;
          return node;
        }
        node.items.push_back(read_node());
      }
    }
    while (at_ < text_.size()) {
      const char d = text_[at_];
      if (std::isspace(static_cast<unsigned char>(d)) || d == '(' || d == ')' || d == ';') break;
      if (static_cast<unsigned char>(d) < 0x20 || static_cast<unsigned char>(d) > 0x7e)
        fail(line_, "a byte that is no printable ASCII character");
      node.symbol += static_cast<char>(std::tolower(static_cast<unsigned char>(d)));
      ++at_;
    }
    return node;
  }

  std::string_view text_;
  std::string file_;
  std::size_t at_ = 0;
  int line_ = 1;
};

bool is_name(const std::string& s) {
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
  });
}

bool is_variable(const std::string& s) { return s.size() > 1 && s[0] == '?' && is_name(s.substr(1)); }

/// What reading a domain or a problem shares: the file's name and the checks of shapes.
class Reader {
 public:
  explicit Reader(SexpReader& sexp) : sexp_(sexp) {}
  [[noreturn]] void fail(const Node& at, const std::string& what) const { sexp_.fail(at.line, what); }

  const std::string& symbol(const Node& n, const std::string& what) const {
    if (n.is_list) fail(n, "expected " + what + ", found a list");
    return n.symbol;
  }
  std::string name(const Node& n, const std::string& what) const {
    const std::string& s = symbol(n, what);
    if (!is_name(s)) fail(n, "'" + s + "' is no name for " + what + " (a letter, then letters, digits, - or _)");
    return s;
  }
  const Node& list(const Node& n, const std::string& what) const {
    if (!n.is_list) fail(n, "expected " + what + ", found '" + n.symbol + "'");
    return n;
  }
  /// `(define (KIND NAME) ...)`: the define list, its name into `name`.
  const Node& definition(const Node& root, const std::string& kind, std::string& name) const {
    const std::string shape = "(define (" + kind + " NAME) ...)";
    const Node& define = list(root, shape);
    if (define.items.size() < 2 || define.items[0].is_list || define.items[0].symbol != "define")
      fail(root, "expected " + shape);
    name = header(define.items[1], kind);
    return define;
  }
  /// `(KEYWORD NAME)`, e.g. (domain kurt): the name.
  std::string header(const Node& n, const std::string& keyword) const {
    const Node& l = list(n, "(" + keyword + " NAME)");
    if (l.items.size() != 2 || l.items[0].is_list || l.items[0].symbol != keyword)
      fail(n, "expected (" + keyword + " NAME)");
    return name(l.items[1], "the " + keyword);
  }
  /// `a b - t c` -> a:t b:t c:object; each name checked by `check_name`.
  template <typename CheckName>
  std::vector<Typed> typed_list(const std::vector<Node>& items, std::size_t from,
                                CheckName check_name) const {
    std::vector<Typed> out;
    std::size_t untyped_from = 0;
    for (std::size_t i = from; i < items.size(); ++i) {
      const Node& n = items[i];
      if (!n.is_list && n.symbol == "-") {
        if (i + 1 >= items.size()) fail(n, "a '-' with no type after it");
        const std::string type = name(items[i + 1], "a type");
        if (untyped_from == out.size()) fail(n, "a '-' with nothing before it to type");
        for (std::size_t k = untyped_from; k < out.size(); ++k) out[k].type = type;
        untyped_from = out.size();
        ++i;
        continue;
      }
      out.push_back(Typed{check_name(n), "object"});
    }
    return out;
  }
  double probability(const Node& n) const {
    const std::string& s = symbol(n, "a probability");
    double p = 0;
    const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), p);
    if (error != std::errc() || end != s.data() + s.size() || !std::isfinite(p) || p < 0 || p > 1)
      fail(n, "'" + s + "' is no probability (a number from 0 to 1)");
    return p;
  }

 private:
  SexpReader& sexp_;
};

/// Lines `; text` for each line of a note.
void write_note(std::ostringstream& out, const std::string& note, const std::string& indent) {
  if (note.empty()) return;
  std::istringstream lines(note);
  std::string line;
  while (std::getline(lines, line)) out << indent << "; " << line << "\n";
}

std::string number(double v) {
  char buffer[32];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, v);
  return error == std::errc() ? std::string(buffer, end) : std::string("0");
}

/// A number for a message: 6 significant digits.
std::string rounded(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}


void write_typed(std::ostringstream& out, const std::vector<Typed>& list) {
  bool first = true;
  for (const auto& t : list) {
    out << (first ? "" : " ") << t.name << " - " << t.type;
    first = false;
  }
}

std::string conjunction(const std::vector<Atom>& positive, const std::vector<Atom>& negative) {
  if (positive.size() + negative.size() == 0) return "(and)";
  std::string s = "(and";
  for (const auto& a : positive) s += " " + text(a);
  for (const auto& a : negative) s += " (not " + text(a) + ")";
  return s + ")";
}

// ---- the domain's checks ------------------------------------------------------------------

struct DomainIndex {
  const Domain& domain;
  std::map<std::string, const PredicateDeclaration*> predicates;
  std::set<std::string> types;
  explicit DomainIndex(const Domain& d) : domain(d) {
    types.insert("object");
    for (const auto& t : d.types) types.insert(t.name);
    for (const auto& p : d.predicates) predicates[p.name] = &p;
  }
};

/// Checks an atom: a declared predicate, its arity, each argument of a type the predicate takes
/// (`type_of` gives an argument's type, or throws).
template <typename TypeOf>
void check_atom(const Reader& r, const Node& at, const DomainIndex& index, const Atom& atom,
                TypeOf type_of) {
  const auto p = index.predicates.find(atom.predicate);
  if (p == index.predicates.end()) r.fail(at, "unknown predicate '" + atom.predicate + "'");
  const auto& params = p->second->parameters;
  if (params.size() != atom.arguments.size())
    r.fail(at, "'" + atom.predicate + "' takes " + std::to_string(params.size()) +
                   " argument(s), given " + std::to_string(atom.arguments.size()));
  for (std::size_t i = 0; i < params.size(); ++i) {
    const std::string type = type_of(atom.arguments[i]);
    if (!is_a(index.domain, type, params[i].type))
      r.fail(at, "argument " + std::to_string(i + 1) + " of '" + atom.predicate + "' is '" +
                     atom.arguments[i] + "' of type " + type + ", not a " + params[i].type);
  }
}

/// `(p a b)` -> Atom; arguments checked by `argument`.
template <typename Argument>
Atom read_atom(const Reader& r, const Node& n, Argument argument) {
  const Node& l = r.list(n, "an atom (PREDICATE ARGUMENTS)");
  if (l.items.empty()) r.fail(n, "an empty atom '()'");
  Atom a;
  a.predicate = r.name(l.items[0], "a predicate");
  if (a.predicate == "and" || a.predicate == "not" || a.predicate == "or" ||
      a.predicate == "probabilistic")
    r.fail(n, "'" + a.predicate + "' where an atom is expected");
  for (std::size_t i = 1; i < l.items.size(); ++i) a.arguments.push_back(argument(l.items[i]));
  return a;
}

/// A literal `(p ...)` or `(not (p ...))` into one of the two lists.
template <typename Argument>
void read_literal(const Reader& r, const Node& n, Argument argument, std::vector<Atom>& positive,
                  std::vector<Atom>& negative) {
  const Node& l = r.list(n, "a literal");
  if (!l.items.empty() && !l.items[0].is_list && l.items[0].symbol == "not") {
    if (l.items.size() != 2) r.fail(n, "(not ...) takes one atom");
    negative.push_back(read_atom(r, l.items[1], argument));
    return;
  }
  positive.push_back(read_atom(r, n, argument));
}

/// `(and lit...)`, `()` or one literal.
template <typename Argument>
void read_conjunction(const Reader& r, const Node& n, Argument argument,
                      std::vector<Atom>& positive, std::vector<Atom>& negative) {
  const Node& l = r.list(n, "a conjunction (and ...)");
  if (l.items.empty()) return;
  if (!l.items[0].is_list && l.items[0].symbol == "and") {
    for (std::size_t i = 1; i < l.items.size(); ++i)
      read_literal(r, l.items[i], argument, positive, negative);
    return;
  }
  if (!l.items[0].is_list && (l.items[0].symbol == "or" || l.items[0].symbol == "imply" ||
                              l.items[0].symbol == "exists" || l.items[0].symbol == "forall" ||
                              l.items[0].symbol == "when"))
    r.fail(n, "'" + l.items[0].symbol + "' is not STRIPS: only (and ...) of atoms and (not atom)");
  read_literal(r, n, argument, positive, negative);
}

/// True when following `name`'s parents comes back to it before reaching object.
bool in_type_cycle(const Domain& d, const std::string& name) {
  std::string at = name;
  for (std::size_t hops = 0; hops <= d.types.size(); ++hops) {
    const auto it = std::find_if(d.types.begin(), d.types.end(),
                                 [&](const Typed& x) { return x.name == at; });
    if (it == d.types.end()) return false;  // object, or a parent checked elsewhere
    at = it->type;
    if (at == name) return true;
  }
  return true;
}

Operator read_action(const Reader& r, const Node& n, const DomainIndex& index) {
  const auto& items = n.items;
  Operator op;
  if (items.size() < 2) r.fail(n, "(:action NAME ...) without a name");
  op.name = r.name(items[1], "the action");
  std::map<std::string, std::string> parameter_types;
  bool have_effect = false;
  std::set<std::string> seen;
  for (std::size_t i = 2; i < items.size(); i += 2) {
    const std::string& key = r.symbol(items[i], "a keyword (:parameters, :precondition, :effect)");
    if (i + 1 >= items.size()) r.fail(items[i], "'" + key + "' with nothing after it");
    if (!seen.insert(key).second) r.fail(items[i], "'" + key + "' twice in action " + op.name);
    const Node& value = items[i + 1];
    if (key == ":parameters") {
      const Node& l = r.list(value, "a parameter list");
      op.parameters = r.typed_list(l.items, 0, [&](const Node& p) {
        const std::string& s = r.symbol(p, "a parameter");
        if (!is_variable(s)) r.fail(p, "'" + s + "' is no parameter (?name)");
        return s;
      });
      for (const auto& p : op.parameters) {
        if (!index.types.count(p.type)) r.fail(value, "unknown type '" + p.type + "'");
        if (!parameter_types.emplace(p.name, p.type).second)
          r.fail(value, "parameter '" + p.name + "' twice");
      }
      continue;
    }
    const auto argument = [&](const Node& a) {
      const std::string& s = r.symbol(a, "an argument");
      if (!parameter_types.count(s))
        r.fail(a, "'" + s + "' is not a parameter of action " + op.name);
      return s;
    };
    const auto type_of = [&](const std::string& s) { return parameter_types.at(s); };
    if (key == ":precondition") {
      read_conjunction(r, value, argument, op.requires_true, op.requires_false);
      for (const auto& a : op.requires_true) check_atom(r, value, index, a, type_of);
      for (const auto& a : op.requires_false) check_atom(r, value, index, a, type_of);
    } else if (key == ":effect") {
      have_effect = true;
      const Node& l = r.list(value, "an effect");
      const Node* body = &l;
      if (!l.items.empty() && !l.items[0].is_list && l.items[0].symbol == "and" &&
          l.items.size() == 2 && l.items[1].is_list && !l.items[1].items.empty() &&
          !l.items[1].items[0].is_list && l.items[1].items[0].symbol == "probabilistic")
        body = &l.items[1];
      if (!body->items.empty() && !body->items[0].is_list &&
          body->items[0].symbol == "probabilistic") {
        if (body->items.size() < 3 || body->items.size() % 2 == 0)
          r.fail(*body, "(probabilistic P EFFECT ...) takes pairs of a probability and an effect");
        double total = 0;
        for (std::size_t k = 1; k < body->items.size(); k += 2) {
          Outcome o;
          o.probability = r.probability(body->items[k]);
          total += o.probability;
          read_conjunction(r, body->items[k + 1], argument, o.add, o.remove);
          op.outcomes.push_back(std::move(o));
        }
        if (total > 1 + 1e-9)
          r.fail(*body, "the outcomes' probabilities add up to " + rounded(total) + ", over 1");
      } else {
        Outcome o;
        read_conjunction(r, value, argument, o.add, o.remove);
        op.outcomes.push_back(std::move(o));
      }
      for (const auto& o : op.outcomes) {
        for (const auto& a : o.add) check_atom(r, value, index, a, type_of);
        for (const auto& a : o.remove) check_atom(r, value, index, a, type_of);
      }
    } else {
      r.fail(items[i], "unknown keyword '" + key + "' in action " + op.name);
    }
  }
  if (!have_effect) r.fail(n, "action " + op.name + " has no :effect");
  return op;
}

}  // namespace

std::string text(const Atom& atom) {
  std::string s = "(" + atom.predicate;
  for (const auto& arg : atom.arguments) s += " " + arg;
  return s + ")";
}

std::string text(const std::vector<Atom>& atoms) {
  std::string s;
  for (const auto& a : atoms) s += (s.empty() ? "" : " ") + text(a);
  return s;
}

bool is_a(const Domain& domain, const std::string& type, const std::string& ancestor) {
  std::string t = type;
  for (std::size_t hops = 0; hops <= domain.types.size() + 1; ++hops) {
    if (t == ancestor || ancestor == "object") return true;
    const auto it = std::find_if(domain.types.begin(), domain.types.end(),
                                 [&](const Typed& d) { return d.name == t; });
    if (it == domain.types.end()) return false;
    t = it->type;
  }
  return false;  // a cycle
}

std::string write(const Domain& domain, Dialect dialect) {
  std::ostringstream out;
  write_note(out, domain.note, "");
  out << "(define (domain " << domain.name << ")\n";
  out << "  (:requirements :strips :typing :negative-preconditions"
      << (dialect == Dialect::Probabilistic ? " :probabilistic-effects" : "") << ")\n";
  if (!domain.types.empty()) {
    out << "  (:types";
    for (const auto& t : domain.types) out << "\n    " << t.name << " - " << t.type;
    out << ")\n";
  }
  out << "  (:predicates";
  for (const auto& p : domain.predicates) {
    out << "\n    (" << p.name << (p.parameters.empty() ? "" : " ");
    write_typed(out, p.parameters);
    out << ")";
  }
  out << ")\n";
  for (const auto& op : domain.operators) {
    out << "\n";
    write_note(out, op.note, "  ");
    out << "  (:action " << op.name << "\n    :parameters (";
    write_typed(out, op.parameters);
    out << ")\n    :precondition " << conjunction(op.requires_true, op.requires_false) << "\n";
    if (dialect == Dialect::Strips || op.outcomes.size() <= 1) {
      if (!op.outcomes.empty() && dialect == Dialect::Strips && op.outcomes.size() > 1) {
        out << "    ; the most likely of " << op.outcomes.size() << " outcomes, p = "
            << number(op.outcomes[0].probability) << "\n";
      } else if (!op.outcomes.empty() && op.outcomes[0].probability < 1) {
        out << "    ; p = " << number(op.outcomes[0].probability) << "\n";
      }
      if (dialect == Dialect::Probabilistic && !op.outcomes.empty() &&
          op.outcomes[0].probability < 1) {
        out << "    :effect (probabilistic " << number(op.outcomes[0].probability) << " "
            << conjunction(op.outcomes[0].add, op.outcomes[0].remove) << "))\n";
        continue;
      }
      const Outcome none;
      const Outcome& o = op.outcomes.empty() ? none : op.outcomes[0];
      out << "    :effect " << conjunction(o.add, o.remove) << ")\n";
      continue;
    }
    out << "    :effect (probabilistic";
    for (const auto& o : op.outcomes)
      out << "\n      " << number(o.probability) << " " << conjunction(o.add, o.remove);
    out << "))\n";
  }
  out << ")\n";
  return out.str();
}

std::string write(const Problem& problem) {
  std::ostringstream out;
  write_note(out, problem.note, "");
  out << "(define (problem " << problem.name << ")\n  (:domain " << problem.domain << ")\n";
  out << "  (:objects";
  for (const auto& o : problem.objects) out << "\n    " << o.name << " - " << o.type;
  out << ")\n  (:init";
  for (const auto& a : problem.init) out << "\n    " << text(a);
  out << ")\n  (:goal " << conjunction(problem.goal_true, problem.goal_false) << "))\n";
  return out.str();
}

Domain read_domain(std::string_view text, const std::string& file) {
  SexpReader sexp(text, file);
  const Node root = sexp.read_all();
  Reader r(sexp);
  Domain d;
  const Node& define = r.definition(root, "domain", d.name);
  std::set<std::string> sections;
  for (std::size_t i = 2; i < define.items.size(); ++i) {
    const Node& s = r.list(define.items[i], "a section (:requirements, :types, :predicates, "
                                            ":action)");
    if (s.items.empty() || s.items[0].is_list) r.fail(s, "a section without a keyword");
    const std::string& key = s.items[0].symbol;
    if (key != ":action" && !sections.insert(key).second) r.fail(s, "'" + key + "' twice");
    if (key == ":requirements") {
      for (std::size_t k = 1; k < s.items.size(); ++k) {
        const std::string& req = r.symbol(s.items[k], "a requirement");
        if (req != ":strips" && req != ":typing" && req != ":negative-preconditions" &&
            req != ":probabilistic-effects")
          r.fail(s.items[k], "requirement '" + req + "' is not supported (:strips, :typing, "
                             ":negative-preconditions, :probabilistic-effects)");
      }
    } else if (key == ":types") {
      if (!d.predicates.empty() || !d.operators.empty())
        r.fail(s, ":types must come before :predicates and actions");
      d.types = r.typed_list(s.items, 1, [&](const Node& n) { return r.name(n, "a type"); });
      std::set<std::string> names{"object"};
      for (const auto& t : d.types)
        if (!names.insert(t.name).second) r.fail(s, "type '" + t.name + "' twice");
      for (const auto& t : d.types)
        if (!names.count(t.type)) r.fail(s, "type '" + t.name + "' derives from unknown '" + t.type + "'");
      for (const auto& t : d.types)
        if (in_type_cycle(d, t.name)) r.fail(s, "type '" + t.name + "' is in a cycle of types");
    } else if (key == ":predicates") {
      if (!d.operators.empty()) r.fail(s, ":predicates must come before the actions");
      const DomainIndex index(d);
      std::set<std::string> names;
      for (std::size_t k = 1; k < s.items.size(); ++k) {
        const Node& p = r.list(s.items[k], "a predicate (NAME ?x - type ...)");
        if (p.items.empty()) r.fail(p, "an empty predicate '()'");
        PredicateDeclaration decl;
        decl.name = r.name(p.items[0], "a predicate");
        if (!names.insert(decl.name).second) r.fail(p, "predicate '" + decl.name + "' twice");
        decl.parameters = r.typed_list(p.items, 1, [&](const Node& n) {
          const std::string& v = r.symbol(n, "a parameter");
          if (!is_variable(v)) r.fail(n, "'" + v + "' is no parameter (?name)");
          return v;
        });
        for (const auto& t : decl.parameters)
          if (!index.types.count(t.type)) r.fail(p, "unknown type '" + t.type + "'");
        d.predicates.push_back(std::move(decl));
      }
    } else if (key == ":action") {
      const DomainIndex index(d);
      Operator op = read_action(r, s, index);
      for (const auto& other : d.operators)
        if (other.name == op.name) r.fail(s, "action '" + op.name + "' twice");
      d.operators.push_back(std::move(op));
    } else {
      r.fail(s, "unknown section '" + key + "'");
    }
  }
  return d;
}

Problem read_problem(std::string_view text, const std::string& file, const Domain& domain) {
  SexpReader sexp(text, file);
  const Node root = sexp.read_all();
  Reader r(sexp);
  Problem p;
  const Node& define = r.definition(root, "problem", p.name);
  const DomainIndex index(domain);
  std::map<std::string, std::string> object_types;
  const auto object = [&](const Node& n) {
    const std::string& s = r.symbol(n, "an object");
    if (!object_types.count(s)) r.fail(n, "unknown object '" + s + "'");
    return s;
  };
  const auto type_of = [&](const std::string& s) { return object_types.at(s); };
  std::set<std::string> sections;
  for (std::size_t i = 2; i < define.items.size(); ++i) {
    const Node& s = r.list(define.items[i], "a section (:domain, :objects, :init, :goal)");
    if (s.items.empty() || s.items[0].is_list) r.fail(s, "a section without a keyword");
    const std::string& key = s.items[0].symbol;
    if (!sections.insert(key).second) r.fail(s, "'" + key + "' twice");
    if (key == ":domain") {
      if (s.items.size() != 2) r.fail(s, "expected (:domain NAME)");
      p.domain = r.name(s.items[1], "the domain");
      if (p.domain != domain.name)
        r.fail(s, "the problem is of domain '" + p.domain + "', the domain read is '" +
                      domain.name + "'");
    } else if (key == ":objects") {
      p.objects = r.typed_list(s.items, 1, [&](const Node& n) { return r.name(n, "an object"); });
      for (const auto& o : p.objects) {
        if (!index.types.count(o.type)) r.fail(s, "object '" + o.name + "' of unknown type '" + o.type + "'");
        if (!object_types.emplace(o.name, o.type).second) r.fail(s, "object '" + o.name + "' twice");
      }
    } else if (key == ":init") {
      for (std::size_t k = 1; k < s.items.size(); ++k) {
        const Node& a = s.items[k];
        if (a.is_list && !a.items.empty() && !a.items[0].is_list && a.items[0].symbol == "not")
          r.fail(a, "(not ...) in :init: what is not listed does not hold");
        Atom atom = read_atom(r, a, object);
        check_atom(r, a, index, atom, type_of);
        p.init.push_back(std::move(atom));
      }
    } else if (key == ":goal") {
      if (s.items.size() != 2) r.fail(s, "expected (:goal (and ...))");
      read_conjunction(r, s.items[1], object, p.goal_true, p.goal_false);
      for (const auto& a : p.goal_true) check_atom(r, s.items[1], index, a, type_of);
      for (const auto& a : p.goal_false) check_atom(r, s.items[1], index, a, type_of);
    } else {
      r.fail(s, "unknown section '" + key + "'");
    }
  }
  if (p.domain.empty()) r.fail(root, "the problem names no (:domain NAME)");
  if (!sections.count(":goal")) r.fail(root, "the problem has no (:goal ...)");
  return p;
}

namespace {
std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PddlError(path + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}
}  // namespace

Domain load_domain(const std::string& path) { return read_domain(read_file(path), path); }

Problem load_problem(const std::string& path, const Domain& domain) {
  return read_problem(read_file(path), path, domain);
}

void save_text(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".part";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!(out << text) || !out.flush()) throw PddlError(path + ": cannot be written");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw PddlError(path + ": cannot be written");
  }
}

}  // namespace macsim::affordances::pddl
