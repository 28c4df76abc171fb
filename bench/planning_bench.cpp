// The planner (macsim::affordances::plan) beside clingo (Debian's gringo package, ASP) on the
// same problems of the hand-written room domain: rooms of 5, 10 and 20 things, plans of 2 to 10
// steps. Each problem is planned by both; the plans must have the same length (both are
// shortest). The domain and problem are translated to an answer-set program here (each operator
// with its most likely outcome, clingo's incremental mode: one step more until the goal holds).
// clingo's figure is its whole process (start-up, grounding, solving), as kurt_plan would pay
// it; its own solve time is printed too. `name value unit` lines.
//   bench_planning [RUNS]   (default 20; from the repository root; clingo from /usr/bin)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "macsim/affordances/planner.h"
#include "macsim/process/child_process.h"
#include <unistd.h>

namespace {

namespace af = macsim::affordances;
namespace pddl = macsim::affordances::pddl;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

/// A PDDL name as an ASP constant ('-' is not allowed there).
std::string constant(const std::string& name) {
  std::string s = name;
  std::replace(s.begin(), s.end(), '-', '_');
  return s;
}

/// An atom as an ASP term, parameters (?x) as the variables `variable` gives.
template <typename Variable>
std::string term(const pddl::Atom& a, Variable variable) {
  std::string s = constant(a.predicate);
  if (a.arguments.empty()) return s;
  s += "(";
  for (std::size_t i = 0; i < a.arguments.size(); ++i)
    s += (i ? "," : "") + (a.arguments[i][0] == '?' ? variable(a.arguments[i]) : constant(a.arguments[i]));
  return s + ")";
}

/// The domain and problem as an answer-set program for clingo's incremental mode: one action a
/// step; a fluent holds on unless an action removes it. Static predicates stay facts.
std::string asp_program(const pddl::Domain& d, const pddl::Problem& p) {
  std::set<std::string> dynamic;
  for (const auto& op : d.operators)
    for (const auto& o : op.outcomes) {
      for (const auto& a : o.add) dynamic.insert(a.predicate);
      for (const auto& a : o.remove) dynamic.insert(a.predicate);
    }
  std::ostringstream out;
  out << "#include <incmode>.\n#program base.\n";
  for (const auto& o : p.objects)
    for (const auto& t : d.types)
      if (pddl::is_a(d, o.type, t.name)) out << "is(" << constant(o.name) << "," << constant(t.name) << ").\n";
  for (const auto& o : p.objects) out << "is(" << constant(o.name) << ",object).\n";
  const auto ground = [](const std::string& v) { return v; };
  for (const auto& a : p.init) {
    if (dynamic.count(a.predicate)) out << "holds(" << term(a, ground) << ",0).\n";
    else out << "static(" << term(a, ground) << ").\n";
  }
  out << "static(none).\n";
  for (const auto& op : d.operators) {
    if (op.outcomes.empty()) continue;
    const pddl::Outcome& o = op.outcomes.front();
    double rest = 1;
    for (const auto& x : op.outcomes) rest -= x.probability;
    if (rest > o.probability || (o.add.empty() && o.remove.empty())) continue;
    std::map<std::string, std::string> names;
    for (std::size_t i = 0; i < op.parameters.size(); ++i) names[op.parameters[i].name] = "P" + std::to_string(i);
    const auto variable = [&](const std::string& v) { return names.at(v); };
    std::string head = constant(op.name);
    if (!op.parameters.empty()) {
      head += "(";
      for (std::size_t i = 0; i < op.parameters.size(); ++i) head += (i ? "," : "") + names[op.parameters[i].name];
      head += ")";
    }
    std::string body;
    for (const auto& param : op.parameters)
      body += (body.empty() ? "" : ", ") + std::string("is(") + names[param.name] + "," + constant(param.type) + ")";
    for (const auto& a : op.requires_true)
      if (!dynamic.count(a.predicate)) body += ", static(" + term(a, variable) + ")";
    for (const auto& a : op.requires_false)
      if (!dynamic.count(a.predicate)) body += ", not static(" + term(a, variable) + ")";
    out << "action(" << head << ")" << (body.empty() ? "" : " :- " + body) << ".\n";
    const auto rule = [&](const char* kind, const pddl::Atom& a) {
      out << kind << "(" << head << "," << term(a, variable) << ") :- action(" << head << ").\n";
    };
    for (const auto& a : op.requires_true)
      if (dynamic.count(a.predicate)) rule("pre", a);
    for (const auto& a : op.requires_false)
      if (dynamic.count(a.predicate)) rule("prenot", a);
    for (const auto& a : o.add) rule("add", a);
    for (const auto& a : o.remove) rule("del", a);
  }
  for (const auto& a : p.goal_true) out << "goal(" << term(a, ground) << ").\n";
  for (const auto& a : p.goal_false) out << "goalnot(" << term(a, ground) << ").\n";
  out << "#program step(t).\n"
         "1 { occurs(A,t) : action(A) } 1.\n"
         ":- occurs(A,t), pre(A,F), not holds(F,t-1).\n"
         ":- occurs(A,t), prenot(A,F), holds(F,t-1).\n"
         "removed(F,t) :- occurs(A,t), del(A,F).\n"
         "holds(F,t) :- occurs(A,t), add(A,F).\n"
         "holds(F,t) :- holds(F,t-1), not removed(F,t).\n"
         "#program check(t).\n"
         "#external query(t).\n"
         ":- query(t), goal(F), not holds(F,t).\n"
         ":- query(t), goalnot(F), holds(F,t).\n"
         "#show occurs/2.\n";
  return out.str();
}

struct ClingoRun {
  double wall = 0, solve = 0;
  int steps = -1;
};

ClingoRun run_clingo(const std::string& program_path, const std::string& output_path) {
  const auto started = Clock::now();
  macsim::process::ChildProcess clingo({"/usr/bin/clingo", "--stats", program_path},
                                       macsim::process::Output::file(output_path));
  clingo.wait_for_exit(std::chrono::minutes(5));
  ClingoRun r;
  r.wall = seconds_since(started);
  std::ifstream in(output_path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::filesystem::remove(output_path);
  if (s.find("SATISFIABLE") == std::string::npos || s.find("UNSATISFIABLE") != std::string::npos) return r;
  // The answer's last line of atoms: count occurs/2.
  const std::regex occurs("occurs\\(");
  const auto answer = s.rfind("Answer:");
  const auto line_end = s.find('\n', s.find('\n', answer) + 1);
  const std::string atoms = s.substr(s.find('\n', answer) + 1, line_end - s.find('\n', answer) - 1);
  r.steps = static_cast<int>(std::distance(std::sregex_iterator(atoms.begin(), atoms.end(), occurs),
                                           std::sregex_iterator()));
  std::smatch m;
  if (std::regex_search(s, m, std::regex("Solving\\s*:\\s*([0-9.]+)s"))) r.solve = std::stod(m[1]);
  return r;
}

/// A room of `things` things (`boxes` of them boxes, the first), the door open or the switch
/// flush as asked; the goal: `on_switch` of the last things on the switch, and beyond the door.
pddl::Problem room(int things, int boxes, bool open, bool flush, int on_switch) {
  pddl::Problem p;
  p.name = "room";
  p.domain = "kurt3d-room";
  p.objects = {{"start", "place"}, {"switch-1", "switch"}, {"door-1", "door"}};
  p.init = {{"robot-at", {"start"}}, {"hand-free", {}}, {"opens", {"switch-1", "door-1"}}};
  if (open) p.init.push_back({"open", {"door-1"}});
  if (flush) p.init.push_back({"flush", {"switch-1"}});
  for (int i = 0; i < things; ++i) {
    const std::string t = "thing-" + std::to_string(i + 1);
    p.objects.push_back({t, "thing"});
    if (i < boxes) p.init.push_back({"box", {t}});
    if (i >= things - on_switch) p.goal_true.push_back({"on", {t, "switch-1"}});
  }
  p.goal_true.push_back({"beyond", {"door-1"}});
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 20;
  if (argc > 2) {
    std::fprintf(stderr, "usage: bench_planning [RUNS]\n");
    return 2;
  }
  if (argc == 2) {
    const std::string arg = argv[1];
    if (arg == "--help" || arg == "-h") {
      std::printf("usage: bench_planning [RUNS]: the planner beside clingo on the hand-written "
                  "room domain (run from the repository root)\n");
      return 0;
    }
    char* end = nullptr;
    const long n = std::strtol(arg.c_str(), &end, 10);
    if (arg.empty() || *end || n < 1 || n > 100000) {
      std::fprintf(stderr, "bench_planning: RUNS must be positive, not '%s'\n", arg.c_str());
      return 2;
    }
    runs = static_cast<int>(n);
  }
  const pddl::Domain domain = pddl::load_domain("affordances/domains/kurt3d_room_by_hand.pddl");
  const bool have_clingo = std::filesystem::exists("/usr/bin/clingo");
  const auto dir = std::filesystem::temp_directory_path() / ("bench_planning_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  struct Case {
    const char* name;
    int things, boxes;
    bool open, flush;
    int on_switch;
  };
  const Case cases[] = {
      {"open_door", 5, 0, true, false, 0},         {"demonstrator", 5, 0, false, false, 0},
      {"push", 5, 1, false, true, 0},              {"two_on_switch", 5, 0, false, false, 2},
      {"demonstrator_20", 20, 0, false, false, 0}, {"push_20", 20, 1, false, true, 0},
      {"two_on_switch_10", 10, 0, false, false, 2}, {"two_on_switch_20", 20, 0, false, false, 2},
  };
  int status = 0;
  for (const Case& c : cases) {
    const pddl::Problem p = room(c.things, c.boxes, c.open, c.flush, c.on_switch);
    std::vector<double> ours;
    af::PlanResult result;
    for (int r = 0; r < runs; ++r) {
      const auto started = Clock::now();
      result = af::plan(domain, p);
      ours.push_back(seconds_since(started));
    }
    const int steps = result.plan ? static_cast<int>(result.plan->steps.size()) : -1;
    std::printf("planning.%s.steps %d steps\n", c.name, steps);
    std::printf("planning.%s.ground_operators %zu operators\n", c.name, result.ground_operators);
    std::printf("planning.%s.expanded %zu states\n", c.name, result.expanded);
    std::printf("planning.%s.astar_median %.3f ms\n", c.name, 1e3 * median(ours));
    if (!have_clingo) continue;
    const std::string program = (dir / (std::string(c.name) + ".lp")).string();
    std::ofstream(program) << asp_program(domain, p);
    std::vector<double> wall, solve;
    int clingo_steps = -1;
    for (int r = 0; r < std::max(1, runs / 4); ++r) {
      const ClingoRun run = run_clingo(program, (dir / "out.txt").string());
      wall.push_back(run.wall);
      solve.push_back(run.solve);
      clingo_steps = run.steps;
    }
    std::printf("planning.%s.clingo_steps %d steps\n", c.name, clingo_steps);
    std::printf("planning.%s.clingo_process_median %.3f ms\n", c.name, 1e3 * median(wall));
    std::printf("planning.%s.clingo_solving_median %.3f ms\n", c.name, 1e3 * median(solve));
    std::printf("planning.%s.clingo_over_astar %.2f ratio\n", c.name, median(wall) / std::max(median(ours), 1e-9));
    if (clingo_steps != steps) {
      std::fprintf(stderr, "bench_planning: %s: clingo's plan has %d steps, A*'s %d\n", c.name, clingo_steps, steps);
      status = 1;
    }
  }
  std::filesystem::remove_all(dir);
  return status;
}
