// The goal families (worlds/goals/) over many layouts, every policy on the same layouts in the
// same run: for each family, seed and policy, macsim --lockstep --seed N and one controller
// stepping it, in two processes over DDS, a few runs side by side. The policies: kurt_plan over
// the domain learned from trials (--affordances DIR), kurt_plan over the hand-written domain (the
// upper bound), kurt_demo (the script), and kurt_plan --policy random (a step chosen at random
// among those the hand-written domain allows, with the same step budget); the plan policies judge
// what stands in the way by DIR/traverse.yml when it is there. Per family and policy:
// the success rate, and of the runs that reached the goal the median plan length, replans, robot
// time and planning time. `name value unit` lines, then one table per family.
//   bench_goals [--domain N] [--jobs J] [--families A,B] [--policies A,B] [--affordances DIR]
//               [SEEDS [FIRST]]   (default 50 seeds from 1001; from the repository root)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "domain_arg.h"
#include "macsim/process/child_process.h"

namespace {

using namespace std::chrono_literals;
using macsim::process::ChildProcess;

const std::vector<std::string> kFamilies = {"demonstrator", "door_open", "push_to_switch",
                                            "stiff_switch", "cluttered_way"};
const std::vector<std::string> kPolicies = {"learned", "hand", "script", "random"};
const char* kByHand = "affordances/domains/kurt3d_room_by_hand.pddl";
// Wall time of one run: three times the controllers' budget of 900 s of robot time (kurt_plan
// ran at 0.8x real time with two runs side by side on two cores, and a run cut at 900 s of wall
// time had not spent its budget). A run cut is counted as not reached, and said so.
constexpr auto kRunLimit = 2700s;

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

/// A number after the last `key` in `text`, or -1.
double number_after(const std::string& text, const std::string& key) {
  const auto at = text.rfind(key);
  return at == std::string::npos ? -1.0 : std::atof(text.c_str() + at + key.size());
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

struct Result {
  bool reached = false;
  double steps = -1, replans = -1, robot_time = -1, planning_ms = -1;
};

struct Run {
  std::string family, policy;
  int seed = 0, domain = 0;
  std::unique_ptr<ChildProcess> sim, controller;
  std::chrono::steady_clock::time_point started;
  bool cut = false;  ///< stopped at kRunLimit
};

/// The controller's command line of `policy`.
std::vector<std::string> controller_argv(const std::string& bin, const std::string& policy,
                                         const std::string& affordances, int domain) {
  const std::string d = std::to_string(domain);
  if (policy == "script") return {bin + "/kurt_demo", "--domain", d, "--lockstep"};
  std::vector<std::string> argv{bin + "/kurt_plan", "--domain", d,
                                "--lockstep",       "--goal",   "through-door"};
  if (policy == "learned") {
    argv.insert(argv.end(), {"--affordances", affordances});
  } else {
    argv.insert(argv.end(), {"--pddl-domain", kByHand});
    // The same perception as the learned policy: DIR's traverse model, when there is one.
    if (!affordances.empty()) argv.insert(argv.end(), {"--affordances", affordances});
    if (policy == "random") argv.insert(argv.end(), {"--policy", "random"});
  }
  return argv;
}

/// What the controller's output says of its run.
Result judge(const std::string& policy, int code, const std::string& output) {
  Result r;
  r.reached = code == 0;
  if (policy == "script") {
    // "... robot time 95.1 s, wall time ..., lift attempts: N"
    r.robot_time = number_after(output, "robot time ");
    return r;
  }
  // "goal reached: yes, plan steps: N, replans: R, robot time: T s, planning time: P ms, ..."
  r.steps = number_after(output, "plan steps: ");
  r.replans = number_after(output, "replans: ");
  r.robot_time = number_after(output, "robot time: ");
  r.planning_ms = number_after(output, "planning time: ");
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::printf(
        "usage: bench_goals [--domain N] [--jobs J] [--families A,B] [--policies A,B] "
        "[--affordances DIR] [SEEDS [FIRST]]\n  Every policy on SEEDS layouts (default 50 from "
        "1001, the layouts kept for measuring) of each goal family (worlds/goals/: %s), in "
        "lock-step, J runs side by side (default 2). Policies: learned (kurt_plan "
        "--affordances DIR: DIR/effects.ppddl, e.g. learn_effects --from-trials "
        "tests/affordances/effect_trials.csv --out DIR; with DIR/traverse.yml, e.g. "
        "affordance_learn "
        "--in tests/tools/affordances/traverse_trials.csv --features shape --save-model DIR, "
        "the plan policies judge what stands in their way by it), hand (kurt_plan over %s), script "
        "(kurt_demo), random (kurt_plan --policy random over the same domain). Prints per family "
        "and policy the success rate and, of the runs that reached the door, the median plan "
        "steps, replans, robot time and planning time; the logs of failed runs are kept. Each "
        "run has a DDS domain of its own among the 80 from --domain (default 10). Run from the "
        "repository root.\n",
        "demonstrator, door_open, push_to_switch, stiff_switch, cluttered_way", kByHand);
    return 0;
  }
  const auto domain_base =
      macsim::bench::take_domain_base(args, "bench_goals", macsim::bench::kLayoutDomainBase);
  if (!domain_base) return 2;
  std::vector<std::string> families = kFamilies, policies = kPolicies;
  std::string affordances;
  int jobs = 2, seeds = 50, first = 1001;
  while (args.size() >= 2 && args[0].rfind("--", 0) == 0) {
    const std::string key = args[0], value = args[1];
    if (key == "--families") {
      families = split(value);
    } else if (key == "--policies") {
      policies = split(value);
    } else if (key == "--affordances") {
      affordances = value;
    } else if (key == "--jobs") {
      jobs = std::atoi(value.c_str());
    } else {
      std::fprintf(stderr, "bench_goals: unknown option %s (--help)\n", key.c_str());
      return 2;
    }
    args.erase(args.begin(), args.begin() + 2);
  }
  if ((!args.empty() && (seeds = std::atoi(args[0].c_str())) <= 0) ||
      (args.size() > 1 && (first = std::atoi(args[1].c_str())) < 0) || args.size() > 2 ||
      jobs < 1 || jobs > 8) {
    std::fprintf(stderr,
                 "bench_goals: SEEDS must be positive, FIRST not negative, J 1-8 (--help)\n");
    return 2;
  }
  for (const auto& f : families) {
    if (!std::filesystem::exists("worlds/goals/" + f + ".xml")) {
      std::fprintf(
          stderr, "bench_goals: no family %s (worlds/goals/%s.xml; run from the repository root)\n",
          f.c_str(), f.c_str());
      return 2;
    }
  }
  for (const auto& p : policies) {
    if (std::find(kPolicies.begin(), kPolicies.end(), p) == kPolicies.end()) {
      std::fprintf(stderr, "bench_goals: no policy %s (learned, hand, script, random)\n",
                   p.c_str());
      return 2;
    }
    if (p == "learned" && !std::filesystem::exists(affordances + "/effects.ppddl")) {
      std::fprintf(
          stderr,
          "bench_goals: the learned policy needs --affordances DIR with DIR/effects.ppddl\n");
      return 2;
    }
  }
  const std::string bin = std::filesystem::canonical("/proc/self/exe").parent_path().string();
  const std::string logs =
      std::filesystem::temp_directory_path() / ("bench_goals_" + std::to_string(getpid()));
  std::filesystem::create_directories(logs);

  // Every run to make, the families' layouts in turn, each layout's policies side by side.
  std::vector<Run> todo;
  int next_domain = 0;
  for (const auto& family : families)
    for (int seed = first; seed < first + seeds; ++seed)
      for (const auto& policy : policies) {
        Run run;
        run.family = family, run.policy = policy, run.seed = seed;
        run.domain = *domain_base + next_domain++ % macsim::bench::kLayoutDomains;
        todo.push_back(std::move(run));
      }
  std::reverse(todo.begin(), todo.end());
  std::map<std::pair<std::string, std::string>, std::vector<Result>> results;
  std::vector<Run> running;
  const auto finish = [&](Run& run, int code) {
    run.sim->stop(10s);
    const std::string output = run.controller->output();
    const Result r = judge(run.policy, code, output);
    results[{run.family, run.policy}].push_back(r);
    std::fprintf(stderr, "%s seed %d %s: exit %d, steps %.0f, replans %.0f, robot time %.1f s%s\n",
                 run.family.c_str(), run.seed, run.policy.c_str(), code, r.steps, r.replans,
                 r.robot_time, run.cut ? " (cut at the wall-time limit)" : "");
    if (r.reached) {
      std::filesystem::remove(run.controller->output_path());
      std::filesystem::remove(run.sim->output_path());
    }
  };
  while (!todo.empty() || !running.empty()) {
    while (static_cast<int>(running.size()) < jobs && !todo.empty()) {
      Run run = std::move(todo.back());
      todo.pop_back();
      const std::string name = run.family + "_" + std::to_string(run.seed) + "_" + run.policy;
      run.sim = std::make_unique<ChildProcess>(
          std::vector<std::string>{bin + "/macsim", "--world",
                                   "worlds/goals/" + run.family + ".xml", "--domain",
                                   std::to_string(run.domain), "--lockstep", "--quiet", "--seed",
                                   std::to_string(run.seed)},
          macsim::process::Output::file(logs + "/macsim_" + name + ".log"));
      run.controller =
          std::make_unique<ChildProcess>(controller_argv(bin, run.policy, affordances, run.domain),
                                         macsim::process::Output::file(logs + "/" + name + ".log"));
      run.started = std::chrono::steady_clock::now();
      running.push_back(std::move(run));
    }
    std::this_thread::sleep_for(200ms);
    for (auto it = running.begin(); it != running.end();) {
      std::optional<int> code = it->controller->wait_for_exit(0ms);
      if (!code && std::chrono::steady_clock::now() - it->started > kRunLimit) {
        it->cut = true;
        code = it->controller->stop();
      }
      if (!code) {
        ++it;
        continue;
      }
      finish(*it, *code);
      it = running.erase(it);
    }
  }

  std::string tables;
  for (const auto& family : families) {
    tables +=
        "\n" + family + " (layouts " + std::to_string(first) + "-" +
        std::to_string(first + seeds - 1) +
        ")\n| policy | reached | plan steps | replans | robot time (s) | planning time (ms) |\n"
        "|---|---|---|---|---|---|\n";
    for (const auto& policy : policies) {
      const auto& rs = results[{family, policy}];
      std::vector<double> steps, replans, times, planning;
      for (const auto& r : rs) {
        if (!r.reached) continue;
        if (r.steps >= 0) steps.push_back(r.steps);
        if (r.replans >= 0) replans.push_back(r.replans);
        if (r.robot_time >= 0) times.push_back(r.robot_time);
        if (r.planning_ms >= 0) planning.push_back(r.planning_ms);
      }
      const std::string key = family + "_" + policy;
      const double rate = rs.empty() ? 0.0 : static_cast<double>(times.size()) / rs.size();
      std::printf("%s_success_rate %.3f ratio\n", key.c_str(), rate);
      std::printf("%s_robot_time_median %.1f s\n", key.c_str(), median(times));
      if (policy != "script") {
        std::printf("%s_plan_steps_median %.1f count\n", key.c_str(), median(steps));
        std::printf("%s_replans_median %.1f count\n", key.c_str(), median(replans));
        std::printf("%s_planning_time_median %.2f ms\n", key.c_str(), median(planning));
      }
      char row[256];
      if (policy == "script")
        std::snprintf(row, sizeof row, "| %s | %zu/%zu | - | - | %.0f | - |\n", policy.c_str(),
                      times.size(), rs.size(), median(times));
      else
        std::snprintf(row, sizeof row, "| %s | %zu/%zu | %.0f | %.0f | %.0f | %.2f |\n",
                      policy.c_str(), times.size(), rs.size(), median(steps), median(replans),
                      median(times), median(planning));
      tables += row;
    }
  }
  std::printf("%s", tables.c_str());
  std::fprintf(stderr, "bench_goals: logs of the runs that did not reach the door in %s\n",
               logs.c_str());
  return 0;
}
