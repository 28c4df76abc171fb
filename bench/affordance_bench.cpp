// Affordance trials at scale: trials per minute of affordance_trials with K = 1, 2 and 4
// simulators (lift, then push and climb at K = 2), each beside K = 1 of the same run; and the
// scoped reset's cost, in process (sim_core on the liftability and trial worlds) and as a
// supervisor round trip against macsim beside a state-hash request (the round trip's baseline).
// `name value unit` lines.
//   bench_affordances [TRIALS]   (default 200 per run; from the repository root)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "macsim/client/child_program.h"
#include "macsim/client/supervisor_client.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// affordance_trials' `trials_per_minute...` figure for one run (0 when it failed).
double trials_per_minute(const std::string& affordance, int instances, int trials, int domain,
                         const std::string& dir) {
  const std::string tag = affordance + "_k" + std::to_string(instances);
  const std::string log = dir + "/" + tag + ".log";
  macsim::client::ChildProgram run(
      {macsim::client::sibling_program("affordance_trials"), "--domain", std::to_string(domain),
       "--instances", std::to_string(instances), "--affordance", affordance, "--trials",
       std::to_string(trials), "--out", dir + "/" + tag + ".csv", "--logs", dir, "--bench"},
      log);
  if (run.wait(std::chrono::hours(2)).value_or(-1) != 0) {
    std::fprintf(stderr, "bench_affordances: %s failed, see %s\n", tag.c_str(), log.c_str());
    return 0;
  }
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("trials_per_minute.", 0) == 0) return std::atof(line.c_str() + line.find(' '));
  }
  return 0;
}

/// Median cost of reset(Everything) in process, microseconds.
double reset_in_process(const std::string& world_file) {
  macsim::World world(macsim::load_world_file(world_file));
  std::vector<double> costs;
  for (int i = 0; i < 200; ++i) {
    for (int s = 0; s < 20; ++s) world.step();
    const auto t = Clock::now();
    world.reset(macsim::ResetScope::Everything);
    costs.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t).count());
  }
  return median(costs);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2 ||
      (argc == 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h"))) {
    std::printf(
        "usage: bench_affordances [TRIALS]   (default 200 trials per run, from the "
        "repository root)\n");
    return argc == 2 ? 0 : 2;
  }
  const int trials = argc == 2 ? std::atoi(argv[1]) : 200;
  if (trials < 1) {
    std::fprintf(stderr, "bench_affordances: TRIALS must be positive\n");
    return 2;
  }
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("bench_affordances_" + std::to_string(getpid())))
          .string();
  std::filesystem::create_directories(dir);
  const int domain = 190 + getpid() % 30;

  // 1. The scoped reset.
  std::printf("reset_in_process.liftability %.1f us\n", reset_in_process("worlds/liftability.xml"));
  std::printf("reset_in_process.affordance_trials %.1f us\n",
              reset_in_process("worlds/affordance_trials.xml"));
  {
    macsim::client::ChildProgram sim(
        {macsim::client::sibling_program("macsim"), "--world", "worlds/liftability.xml", "--domain",
         std::to_string(domain), "--lockstep", "--cameras", "off"},
        dir + "/macsim_reset.log");
    macsim::dds::Participant participant({domain, "", "bench_affordances"});
    macsim::client::SupervisorClient supervisor(participant);
    if (!supervisor.wait_for_server(std::chrono::seconds(30))) {
      std::fprintf(stderr, "bench_affordances: no simulator, see %s/macsim_reset.log\n",
                   dir.c_str());
      return 1;
    }
    std::vector<double> reset, hash;
    for (int i = 0; i < 400; ++i) {
      const bool resetting = i % 2 == 0;  // alternating: both see the same machine noise
      const auto t = Clock::now();
      auto reply = supervisor.call(
          resetting ? macsim::client::supervisor::reset(macsim_msgs::msg::dds_::RESET_EVERYTHING)
                    : macsim::client::supervisor::state_hash());
      const double us = std::chrono::duration<double, std::micro>(Clock::now() - t).count();
      if (!reply || reply->code() != 0) {
        std::fprintf(stderr, "bench_affordances: a supervisor request failed\n");
        return 1;
      }
      (resetting ? reset : hash).push_back(us);
    }
    std::printf("reset_round_trip.liftability %.1f us\n", median(reset));
    std::printf("state_hash_round_trip.liftability %.1f us\n", median(hash));
    std::printf("ratio.reset_over_state_hash_round_trip %.2f x\n", median(reset) / median(hash));
  }

  // 2. Trials per minute.
  const double k1 = trials_per_minute("lift", 1, trials, domain, dir);
  std::printf("trials_per_minute.lift.k1 %.1f trials/min\n", k1);
  for (int k : {2, 4}) {
    const double rate = trials_per_minute("lift", k, trials, domain, dir);
    std::printf("trials_per_minute.lift.k%d %.1f trials/min\n", k, rate);
    std::printf("speedup.lift.k%d_over_k1 %.2f x\n", k, k1 > 0 ? rate / k1 : 0.0);
  }
  for (const char* a : {"push", "climb"}) {
    std::printf("trials_per_minute.%s.k2 %.1f trials/min\n", a,
                trials_per_minute(a, 2, trials, domain, dir));
  }
  std::filesystem::remove_all(dir);
  return 0;
}
