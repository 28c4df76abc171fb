// Affordance trials at scale: trials per minute of affordance_trials with K = 1 and 2 simulators
// for lift, push, climb, stack and traverse (and K = 4 for lift), each beside the bound measured
// in the same run: the trials' own steps at the in-process step rate of the trial world (sim_core
// alone, no DDS, the robot driving), on min(K, cores) cores; efficiency = trials/min over that
// bound. And the scoped reset's cost, in process (sim_core on the liftability and trial worlds) and
// as a supervisor round trip against macsim beside a state-hash request (the round trip's
// baseline). `name value unit` lines.
//   bench_affordances [TRIALS] [--domain N]   (default 200 per run; from the repository root)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "macsim/client/supervisor_client.h"
#include "macsim/process/child_process.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "supervisor/supervisor_codec.h"
#include "trial_record.h"
#include "trial_robot.h"
#include "trial_spec.h"

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// What one affordance_trials run came to.
struct TrialRun {
  double per_minute = 0;       ///< trials/min, the simulators' start-up included (0: it failed)
  double running = 0;          ///< trials/min from the first trial's start
  double start_up = 0;         ///< s before the first trial began (simulators started, first look)
  double steps_per_trial = 0;  ///< mean of its rows' steps
};

/// Mean of the `steps` column of a trials file (0 when there is none).
double mean_steps(const std::string& csv) {
  if (!std::filesystem::exists(csv)) return 0;
  const affordances::CsvTable table = affordances::read_csv(csv);
  const auto column = table.column("steps");
  if (!column || table.rows.empty()) return 0;
  double sum = 0;
  for (const auto& row : table.rows) sum += std::atof(row[*column].c_str());
  return sum / static_cast<double>(table.rows.size());
}

/// One affordance_trials run with K started simulators.
TrialRun run_trials(const std::string& affordance, int instances, int trials, int domain,
                    const std::string& dir) {
  const std::string tag = affordance + "_k" + std::to_string(instances);
  const std::string log = dir + "/" + tag + ".log";
  macsim::process::ChildProcess run(
      {macsim::process::sibling_program("affordance_trials"), "--domain", std::to_string(domain),
       "--instances", std::to_string(instances), "--affordance", affordance, "--trials",
       std::to_string(trials), "--out", dir + "/" + tag + ".csv", "--logs", dir, "--bench"},
      macsim::process::Output::file(log));
  if (run.wait_for_exit(std::chrono::hours(2)).value_or(-1) != 0) {
    std::fprintf(stderr, "bench_affordances: %s failed, see %s\n", tag.c_str(), log.c_str());
    return {};
  }
  TrialRun result;
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);) {
    const double value = std::atof(line.c_str() + line.find(' '));
    if (line.rfind("trials_per_minute.", 0) == 0) result.per_minute = value;
    if (line.rfind("trials_per_minute_running.", 0) == 0) result.running = value;
    if (line.rfind("start_up.", 0) == 0) result.start_up = value;
  }
  result.steps_per_trial = mean_steps(dir + "/" + tag + ".csv");
  return result;
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

/// sim_core alone on the trial world: steps per second of one core over `trials` of the
/// affordance's own trials (seeds 1, 2, ...: the object or ramp each spawns), each `steps` steps
/// from a scoped reset (the reset itself not counted), the robot acting as the trials act: the
/// crane aside while it looks (0.806 s), then driving at 0.4 m/s into the object for about as
/// long as the affordance drives (lift 1 s, push 3 s, climb to the end) with the boom up and
/// aside, or (lift) the boom swung ahead, lowered with the magnet on and raised again; drive
/// commands renewed as a controller would.
double in_process_step_rate(const std::string& world_file, affordances::Affordance affordance,
                            int steps, int trials) {
  using affordances::Affordance;
  const double look = 0.806;
  // When the drive starts and how long it lasts; stack carries first, traverse turns the
  // scanner one revolution first.
  double drive_at = look, drive = 1e9;
  if (affordance == Affordance::Lift) drive = 1.0;
  if (affordance == Affordance::Push) drive = 3.0;
  if (affordance == Affordance::Stack) drive_at = look + 3.5, drive = 0.6;
  if (affordance == Affordance::Traverse) drive_at = look + 1.04;
  // (time, slew, lift, hoist, magnet): the crane's commands of a trial.
  struct CraneAt {
    double at, slew, lift, hoist;
    bool magnet;
  };
  std::vector<CraneAt> crane{{0.0, -0.75, 0.0, 0.0, false}};
  if (affordance == Affordance::Lift) {
    crane.push_back({look, 0.0, 0.2, 0.0, false});
    crane.push_back({look + 1.5, 0.0, 0.2, 0.12, true});
    crane.push_back({look + 2.3, 0.0, 0.5, 0.0, true});
  } else if (affordance == Affordance::Stack) {  // pick beside, carry, lower onto the base
    crane.push_back({look, 1.3, 0.0, 0.0, false});
    crane.push_back({look + 2.0, 1.3, 0.0, 0.3, true});
    crane.push_back({look + 3.0, 1.3, 0.3, 0.0, true});
    crane.push_back({look + 4.2, 0.0, 0.3, 0.1, true});
    crane.push_back({look + 6.0, 0.0, 0.3, 0.1, false});
  } else {
    crane.push_back({look, -0.75, 0.6, 0.0, false});
  }
  macsim::World world(macsim::load_world_file(world_file));
  const double dt = world.step_size();
  double seconds = 0;
  uint64_t stepped = 0;
  for (int trial = 0; trial < trials + 2; ++trial) {
    world.reset(macsim::ResetScope::Everything);
    const auto spec = affordances::make_trial(affordance, affordances::Generator::Material,
                                              static_cast<uint64_t>(trial % trials + 1));
    std::string error;
    auto object = macsim::codec::spec_of(affordances::trial_object(spec), error);
    if (!object || !world.edit().create_object(*object).ok()) {
      std::fprintf(stderr, "bench_affordances: trial %d's object: %s\n", trial, error.c_str());
      return 0;
    }
    if (affordance == Affordance::Stack) {
      auto carried = macsim::codec::spec_of(affordances::carried_object(spec.carried), error);
      if (!carried || !world.edit().create_object(*carried).ok()) {
        std::fprintf(stderr, "bench_affordances: trial %d's carried object: %s\n", trial,
                     error.c_str());
        return 0;
      }
    }
    auto& robot = *world.robots().front();
    std::size_t next_crane = 0;
    const auto t = Clock::now();
    for (int s = 0; s < steps; ++s) {
      const double now = world.time();
      if (next_crane < crane.size() && now + dt / 2 >= crane[next_crane].at) {
        const CraneAt& c = crane[next_crane++];
        robot.execute(macsim::robot::CraneTarget{c.slew, c.lift, c.hoist}, now);
        robot.execute(macsim::robot::MagnetSwitch{c.magnet}, now);
      }
      if (s % 100 == 0 || std::fabs(now - drive_at) < dt / 2 ||
          std::fabs(now - drive_at - drive) < dt / 2)
        robot.execute(
            macsim::robot::Twist{
                now + dt / 2 >= drive_at && now + dt / 2 < drive_at + drive ? 0.4 : 0.0, 0.0},
            now);
      if (affordance == Affordance::Traverse && std::fabs(now - look) < dt / 2)
        robot.execute(macsim::robot::RotunitSpeed{2 * M_PI}, now);
      if (affordance == Affordance::Traverse && std::fabs(now - drive_at) < dt / 2)
        robot.execute(macsim::robot::RotunitSpeed{0.0}, now);
      world.step();
    }
    if (trial >= 2) {  // the first two warm the caches
      seconds += std::chrono::duration<double>(Clock::now() - t).count();
      stepped += static_cast<uint64_t>(steps);
    }
  }
  return stepped / seconds;
}

}  // namespace

int main(int argc, char** argv) {
  // [TRIALS] [--domain N]: the runs use domains N..N+3 (default 90 + pid % 6: 90-98, below the
  // tests' 100-232).
  int trials = 200, domain = 90 + getpid() % 6;
  bool help = false, bad = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    char* end = nullptr;
    if (arg == "--help" || arg == "-h") {
      help = true;
    } else if (arg == "--domain" && i + 1 < argc) {
      const long d = std::strtol(argv[++i], &end, 10);
      bad |= *end != '\0' || d < 0 || d + 3 > 232;
      domain = static_cast<int>(d);
    } else {
      const long n = std::strtol(arg.c_str(), &end, 10);
      if (*end != '\0' || n < 1) {
        std::fprintf(stderr, "bench_affordances: TRIALS must be positive, --domain 0..229\n");
        return 2;
      }
      trials = static_cast<int>(n);
    }
  }
  if (bad) {
    std::fprintf(stderr, "bench_affordances: --domain takes 0..229 (see --help)\n");
    return 2;
  }
  if (help) {
    std::printf(
        "usage: bench_affordances [TRIALS] [--domain N]   (default 200 trials per run; the "
        "simulators on domains N..N+3; from the repository root)\n");
    return 0;
  }
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("bench_affordances_" + std::to_string(getpid())))
          .string();
  std::filesystem::create_directories(dir);

  // 1. The scoped reset.
  std::printf("reset_in_process.liftability %.1f us\n", reset_in_process("worlds/liftability.xml"));
  std::printf("reset_in_process.affordance_trials %.1f us\n",
              reset_in_process("worlds/affordance_trials.xml"));
  {
    macsim::process::ChildProcess sim(
        {macsim::process::sibling_program("macsim"), "--world", "worlds/liftability.xml",
         "--domain", std::to_string(domain), "--lockstep", "--cameras", "off"},
        macsim::process::Output::file(dir + "/macsim_reset.log"));
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

  // 2. Trials per minute beside the bound. The in-process rate is measured right before and
  // right after each run (as many steps per trial as the run's trials took) and averaged: this
  // machine's speed drifts over minutes, and the bound must be the machine the run had.
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (const char* a : {"lift", "push", "climb", "stack", "traverse"}) {
    const auto affordance = *affordances::affordance_from_name(a);
    const auto steps_of = [&](int k) {  // the last run's steps per trial (a first guess before)
      const double mean =
          mean_steps(dir + "/" + std::string(a) + "_k" + std::to_string(k) + ".csv");
      return mean > 0 ? static_cast<int>(std::lround(mean)) : 2500;
    };
    double k1 = 0;
    for (int k : {1, 2, 4}) {
      if (k == 4 && std::string(a) != "lift") continue;
      const double before = in_process_step_rate("worlds/affordance_trials.xml", affordance,
                                                 k == 1 ? 2500 : steps_of(1), 10);
      const TrialRun run = run_trials(a, k, trials, domain, dir);
      if (!(run.steps_per_trial > 0)) {
        std::printf("efficiency.%s.k%d 0 ratio\n", a, k);  // the run failed (said above)
        continue;
      }
      const double after =
          in_process_step_rate("worlds/affordance_trials.xml", affordance,
                               static_cast<int>(std::lround(run.steps_per_trial)), 10);
      const double rate = (before + after) / 2;
      // Each trial's steps at the in-process rate, on as many cores as instances can use.
      const double bound =
          run.steps_per_trial > 0 ? 60.0 * rate / run.steps_per_trial * std::min(k, cores) : 0.0;
      std::printf("in_process_step_rate.%s.k%d %.0f steps/s\n", a, k, rate);
      // Trials per minute once the simulators run (their start-up, a fixed cost of a run, is
      // printed on its own), and with it.
      std::printf("trials_per_minute.%s.k%d %.1f trials/min\n", a, k, run.running);
      std::printf("trials_per_minute_with_start_up.%s.k%d %.1f trials/min\n", a, k, run.per_minute);
      std::printf("start_up.%s.k%d %.2f s\n", a, k, run.start_up);
      std::printf("steps_per_trial.%s.k%d %.0f steps\n", a, k, run.steps_per_trial);
      std::printf("bound.%s.k%d %.1f trials/min\n", a, k, bound);
      std::printf("efficiency.%s.k%d %.2f ratio\n", a, k, bound > 0 ? run.running / bound : 0.0);
      if (k == 1) {
        k1 = run.running;
      } else {
        std::printf("speedup.%s.k%d_over_k1 %.2f x\n", a, k, k1 > 0 ? run.running / k1 : 0.0);
      }
    }
  }
  std::filesystem::remove_all(dir);
  return 0;
}
