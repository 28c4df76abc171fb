// The final demonstrator over many layouts: for each seed, macsim --lockstep --seed N on the
// demo world and kurt_demo --lockstep stepping it, in two processes over DDS. Prints the success
// rate, the median and 90th percentile of the robot (sim) time and the wall time per run, and
// their ratio (how much faster than real time a run is), and how often the first can tried came
// up (with a lift model, --affordances, against nearest first without). `name value unit` lines.
//   bench_demo [--world FILE] [--affordances DIR] [SEEDS [FIRST]]
//   (default worlds/DemoWorld_v1.xml, 50 seeds from 1; from the repository root)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "domain_arg.h"
#include "macsim/process/child_process.h"

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double rank = p * (v.size() - 1);
  const auto lo = static_cast<std::size_t>(rank);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (rank - lo) * (v[hi] - v[lo]);
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 50, first = 1;
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::printf(
        "usage: bench_demo [--domain N] [--world FILE] [--affordances DIR] [SEEDS [FIRST]]\n  "
        "kurt_demo "
        "against macsim in lock-step on SEEDS layouts of FILE (default "
        "worlds/DemoWorld_v1.xml; 50 from seed 1), with the lift model DIR/lift.yml if given; "
        "prints the success rate, how often the first can tried came up, the lift attempts, "
        "and the median and p90 robot and wall time per run. Each run has a DDS domain of its "
        "own among the 80 from --domain (default 10). Run from the repository root.\n");
    return 0;
  }
  const auto domain_base =
      macsim::bench::take_domain_base(args, "bench_demo", macsim::bench::kLayoutDomainBase);
  if (!domain_base) return 2;
  std::string world = "worlds/DemoWorld_v1.xml", affordances;
  while (args.size() >= 2 && (args[0] == "--world" || args[0] == "--affordances")) {
    (args[0] == "--world" ? world : affordances) = args[1];
    args.erase(args.begin(), args.begin() + 2);
  }
  if ((!args.empty() && (seeds = std::atoi(args[0].c_str())) <= 0) ||
      (args.size() > 1 && (first = std::atoi(args[1].c_str())) < 0) || args.size() > 2) {
    std::fprintf(stderr, "bench_demo: SEEDS must be positive and FIRST not negative (--help)\n");
    return 2;
  }
  if (!std::filesystem::exists(world)) {
    std::fprintf(stderr, "bench_demo: run it from the repository root (%s not found)\n",
                 world.c_str());
    return 2;
  }
  const std::string bin = std::filesystem::canonical("/proc/self/exe").parent_path().string();
  const std::string logs =
      std::filesystem::temp_directory_path() / ("bench_demo_" + std::to_string(getpid()));
  std::filesystem::create_directories(logs);
  std::vector<double> sim_times, wall_times;
  std::vector<int> failed;
  int lift_attempts = 0, first_lifts = 0;
  for (int seed = first; seed < first + seeds; ++seed) {
    const std::string domain = std::to_string(*domain_base + seed % macsim::bench::kLayoutDomains);
    const std::string sim_log = logs + "/macsim_" + std::to_string(seed) + ".log";
    const std::string demo_log = logs + "/kurt_demo_" + std::to_string(seed) + ".log";
    macsim::process::ChildProcess sim({bin + "/macsim", "--world", world, "--domain", domain,
                                       "--lockstep", "--seed", std::to_string(seed)},
                                      macsim::process::Output::file(sim_log));
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> demo_argv{bin + "/kurt_demo", "--domain", domain, "--lockstep"};
    if (!affordances.empty()) demo_argv.insert(demo_argv.end(), {"--affordances", affordances});
    macsim::process::ChildProcess demo(demo_argv, macsim::process::Output::file(demo_log));
    const auto ended = demo.wait_for_exit(std::chrono::seconds(600));
    const int code = ended ? *ended : demo.stop();  // stopped after 600 s
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sim.stop(std::chrono::seconds(10));
    // The robot time is in kurt_demo's last line: "... robot time 95.1 s, wall time ...".
    std::ifstream in(demo_log);
    std::string line, last;
    while (std::getline(in, line)) last = line;
    double sim_time = 0;
    const auto at = last.find("robot time ");
    if (at != std::string::npos) sim_time = std::atof(last.c_str() + at + 11);
    const auto tries = last.find("lift attempts: ");
    const int attempts = tries == std::string::npos ? 0 : std::atoi(last.c_str() + tries + 15);
    lift_attempts += attempts;
    if (code == 0 && attempts == 1) ++first_lifts;
    std::fprintf(stderr,
                 "seed %d: exit %d, robot time %.1f s, wall time %.1f s, lift attempts %d\n", seed,
                 code, sim_time, wall, attempts);
    if (code != 0) {
      failed.push_back(seed);
      continue;
    }
    sim_times.push_back(sim_time);
    wall_times.push_back(wall);
  }
  std::vector<double> speed;
  for (std::size_t i = 0; i < sim_times.size(); ++i) speed.push_back(sim_times[i] / wall_times[i]);
  std::printf("demo_runs %d count\n", seeds);
  std::printf("demo_successes %zu count\n", sim_times.size());
  std::printf("demo_success_rate %.3f ratio\n", static_cast<double>(sim_times.size()) / seeds);
  std::printf("demo_first_lift_rate %.3f ratio\n", static_cast<double>(first_lifts) / seeds);
  std::printf("demo_lift_attempts_mean %.2f count\n", static_cast<double>(lift_attempts) / seeds);
  std::printf("demo_sim_time_median %.1f s\n", percentile(sim_times, 0.5));
  std::printf("demo_sim_time_p90 %.1f s\n", percentile(sim_times, 0.9));
  std::printf("demo_wall_time_median %.1f s\n", percentile(wall_times, 0.5));
  std::printf("demo_wall_time_p90 %.1f s\n", percentile(wall_times, 0.9));
  std::printf("demo_faster_than_real_time_median %.2f ratio\n", percentile(speed, 0.5));
  if (!failed.empty()) {
    std::string list;
    for (int s : failed) list += " " + std::to_string(s);
    std::fprintf(stderr, "bench_demo: failed seeds:%s (logs in %s)\n", list.c_str(), logs.c_str());
  } else {
    std::filesystem::remove_all(logs);
  }
  return 0;
}
