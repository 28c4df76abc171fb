// affordance_trials: runs lift, push or climb trials on lock-step simulators and writes one CSV
// row per trial: what the robot perceived, the object's true properties, the label measured on
// the world state, sim and wall time. Trials run on K simulators at once; a run that was killed
// resumes where it stopped.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "macsim/client/child_program.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/data_files.h"
#include "trial_pool.h"

namespace {

using namespace affordances;
using Clock = std::chrono::steady_clock;

/// One updating line on a terminal, a plain line every 10 s otherwise.
class Progress {
 public:
  Progress(int total, int already) : total_(total), already_(already), tty_(isatty(2)) {}
  void update(int done, bool last = false) {
    const auto now = Clock::now();
    if (!last && !tty_ && now - printed_ < std::chrono::seconds(10)) return;
    if (!last && tty_ && now - printed_ < std::chrono::milliseconds(200)) return;
    printed_ = now;
    const double minutes = std::chrono::duration<double>(now - start_).count() / 60.0;
    const double rate = minutes > 0 ? done / minutes : 0.0;
    const int left = total_ - already_ - done;
    char line[200];
    std::snprintf(line, sizeof line, "trials %d/%d, %.0f trials/min, ETA %s", already_ + done,
                  total_, rate, rate > 0 ? eta(left / rate * 60).c_str() : "-");
    std::fprintf(stderr, tty_ ? "\r%s\033[K%s" : "%s%s", line, tty_ && !last ? "" : "\n");
    std::fflush(stderr);
  }

 private:
  static std::string eta(double seconds) {
    char text[32];
    const int s = static_cast<int>(seconds + 0.5);
    if (s >= 3600)
      std::snprintf(text, sizeof text, "%dh%02dm", s / 3600, s / 60 % 60);
    else
      std::snprintf(text, sizeof text, "%dm%02ds", s / 60, s % 60);
    return text;
  }
  int total_, already_;
  bool tty_;
  Clock::time_point start_ = Clock::now(), printed_{};
};

std::vector<int> parse_domains(const std::string& list) {
  std::vector<int> domains;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const long d = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end || d < 0 || d > macsim::dds::kMaxDomainId) return {};
    domains.push_back(static_cast<int>(d));
  }
  return domains;
}

/// The row's key: affordance, generator, seed (the first three columns).
std::string key_of(const std::string& row) {
  std::size_t comma = 0;
  for (int i = 0; i < 3 && comma != std::string::npos; ++i) comma = row.find(',', comma + 1);
  return row.substr(0, comma);
}

/// Rows sorted by affordance, generator and seed.
void sort_rows(std::vector<std::string>& rows) {
  auto key = [](const std::string& row) {
    std::stringstream in(row);
    std::string a, g, seed;
    std::getline(in, a, ',');
    std::getline(in, g, ',');
    std::getline(in, seed, ',');
    return std::make_tuple(a, g, std::stoull(seed));
  };
  std::stable_sort(rows.begin(), rows.end(),
                   [&](const std::string& x, const std::string& y) { return key(x) < key(y); });
}

/// A row without its last two columns (instance, wall time): what must repeat bit for bit.
std::string result_part(const std::string& row) {
  auto cut = row.rfind(',');
  cut = row.rfind(',', cut - 1);
  return row.substr(0, cut);
}

}  // namespace

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{-1, "", "affordance_trials"};
  int trials = 100, instances = 1, repeat = 1;
  double first_seed = 1, timeout = 10;
  std::string affordance_name = "lift", generator_name = "material", out, world, attach, log_dir,
              cameras = "320x240";
  double camera_rate = 1.25;
  bool hash_every_step = false, bench = false;
  macsim::dds::CommandLine cli(
      "affordance_trials",
      "Runs affordance trials on lock-step simulators: each trial resets the world, spawns an "
      "object (or a ramp) drawn from its seed, lets the robot perceive it with its cameras and "
      "laser and try the affordance, and labels the outcome from the world state. One CSV row "
      "per trial; a killed run resumes (rows already in --out are not run again).\n"
      "It starts --instances simulators on domains N, N+1, ... (--domain N is required) or uses "
      "running ones (--attach D1,D2,...; started as macsim --lockstep --camera-rate HZ).\n"
      "Exit 0: every trial has its row; 1: trials are missing (every instance lost, or refused); "
      "2: usage; 3: --repeat found a trial that did not repeat bit for bit.");
  cli.participant_options(&participant);
  cli.option("affordance", "lift|push|climb", "the affordance tried (default lift)",
             &affordance_name);
  cli.option("generator", "material|figure11",
             "how objects are drawn: material (liftability from mass and magnet) or figure11 "
             "(heavy objects are blue); default material",
             &generator_name);
  cli.option("trials", "N", "number of trials (default 100)", &trials);
  cli.option("seed", "S", "seed of the first trial; trial i has seed S+i (default 1)", &first_seed);
  cli.option("instances", "K", "simulators to start (default 1)", &instances);
  cli.option("attach", "D1,D2,...", "use running lock-step simulators on these domains", &attach);
  cli.option("out", "FILE.csv", "the trial rows (appended to when it exists: resume)", &out);
  cli.option("world", "FILE",
             "world of the started simulators (default worlds/affordance_trials.xml)", &world);
  cli.option("cameras", "WxH", "camera size of the started simulators (default 320x240)", &cameras);
  cli.option("camera-rate", "HZ",
             "camera rate of the simulators (default 1.25: a pair at the perception instant)",
             &camera_rate);
  cli.option("timeout", "SECONDS", "an instance silent this long (wall time) is lost (default 10)",
             &timeout);
  cli.option("logs", "DIR", "logs of the started simulators (default a fresh /tmp directory)",
             &log_dir);
  cli.option("repeat", "R", "run every trial R times and check the rows are identical (default 1)",
             &repeat);
  cli.flag("hash-every-step", "step one step per request, so the trace hash covers every step",
           &hash_every_step);
  cli.flag("bench",
           "print trials per minute and the scoped reset's round trip as `name value unit`",
           &bench);
  if (auto code = cli.parse(argc, argv)) return *code;

  const auto affordance = affordance_from_name(affordance_name);
  const auto generator = generator_from_name(generator_name);
  const std::vector<int> attached = attach.empty() ? std::vector<int>{} : parse_domains(attach);
  auto usage = [](const std::string& message) {
    std::cerr << "affordance_trials: " << message << " (see --help)\n";
    return 2;
  };
  if (!affordance)
    return usage("unknown --affordance '" + affordance_name + "' (lift, push, climb)");
  if (!generator) return usage("unknown --generator '" + generator_name + "' (material, figure11)");
  if (out.empty()) return usage("say where the rows go: --out FILE.csv");
  if (trials < 1 || instances < 1 || instances > 32 || repeat < 1 || first_seed < 0 ||
      !(timeout > 0) || !(camera_rate > 0))
    return usage(
        "--trials, --repeat, --timeout and --camera-rate must be positive, --instances 1..32, "
        "--seed >= 0");
  if (!attach.empty() && attached.empty())
    return usage("--attach takes domains 0..232: '" + attach + "'");
  if (attached.empty() && participant.domain < 0)
    return usage(
        "say on which DDS domains to run: --domain N (simulators on N..N+K-1) or --attach");
  if (attached.empty() && participant.domain + instances - 1 > macsim::dds::kMaxDomainId)
    return usage("domains " + std::to_string(participant.domain) + ".." +
                 std::to_string(participant.domain + instances - 1) + " go past 232");
  if (world.empty()) {
    world = macsim::dds::data_file("worlds/affordance_trials.xml");
  }
  if (attached.empty() && !std::filesystem::exists(world))
    return usage("no world file '" + world + "' (give --world)");

  // Resume: the rows already there are kept and not run again.
  std::vector<std::string> rows;
  std::set<std::string> have;
  if (std::filesystem::exists(out) && std::filesystem::file_size(out) > 0) {
    try {
      const CsvTable table = read_csv(out);
      std::string joined;
      for (std::size_t i = 0; i < table.columns.size(); ++i)
        joined += (i ? "," : "") + table.columns[i];
      if (joined != csv_header()) {
        std::cerr << "affordance_trials: " << out
                  << " has other columns than this version writes\n";
        return 2;
      }
      for (const auto& fields : table.rows) {
        std::string row;
        for (std::size_t i = 0; i < fields.size(); ++i) row += (i ? "," : "") + fields[i];
        have.insert(key_of(row));
        rows.push_back(row);
      }
    } catch (const std::exception& e) {
      std::cerr << "affordance_trials: " << e.what() << "\n";
      return 2;
    }
  }
  std::vector<TrialSpec> todo;
  const auto first = static_cast<uint64_t>(first_seed);
  int wanted = 0;
  for (int i = 0; i < trials; ++i) {
    const TrialSpec spec = make_trial(*affordance, *generator, first + static_cast<uint64_t>(i));
    ++wanted;
    if (have.count(trial_key(name(spec.affordance), name(spec.generator), spec.seed))) continue;
    for (int r = 0; r < repeat; ++r) todo.push_back(spec);
  }
  const int already = wanted - static_cast<int>(todo.size()) / repeat;
  if (already > 0)
    std::fprintf(stderr, "affordance_trials: %d trials already in %s\n", already, out.c_str());

  // The file as it stands (a row cut short by a kill is dropped), then a row per trial done.
  {
    std::ofstream file(out, std::ios::trunc);
    file << csv_header() << "\n";
    for (const auto& row : rows) file << row << "\n";
    if (!file) {
      std::cerr << "affordance_trials: cannot write " << out << "\n";
      return 2;
    }
  }
  std::ofstream file(out, std::ios::app);

  PoolOptions pool;
  pool.instances = instances;
  pool.first_domain = participant.domain;
  pool.attach = attached;
  pool.world = world;
  pool.cameras = cameras;
  pool.instance.profile = participant.profile_file;
  pool.instance.camera_rate = camera_rate;
  pool.instance.hash_every_step = hash_every_step;
  pool.instance.timeout = std::chrono::milliseconds(static_cast<int64_t>(timeout * 1000));
  if (log_dir.empty()) {
    log_dir =
        (std::filesystem::temp_directory_path() / ("affordance_trials_" + std::to_string(getpid())))
            .string();
  }
  std::filesystem::create_directories(log_dir);
  pool.log_dir = log_dir;

  Progress progress(wanted * repeat, already * repeat);
  std::map<std::string, std::string> first_result;  // --repeat: the first row of each trial
  int mismatches = 0, done = 0;
  double sim_seconds = 0;
  const auto start = Clock::now();
  const PoolSummary summary = TrialPool(pool).run(todo, [&](const TrialRecord& record) {
    const std::string row = csv_row(record);
    const std::string key = key_of(row);
    auto [seen, inserted] = first_result.emplace(key, result_part(row));
    if (inserted) {
      file << row << "\n" << std::flush;
      rows.push_back(row);
    } else if (seen->second != result_part(row)) {
      ++mismatches;
      std::fprintf(stderr, "\naffordance_trials: trial %s differs when repeated:\n  %s\n  %s\n",
                   key.c_str(), seen->second.c_str(), result_part(row).c_str());
    }
    sim_seconds += record.sim_time;
    progress.update(++done);
  });
  progress.update(done, true);
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();

  // Sorted by seed: the same trials give the same file, however many instances ran them.
  file.close();
  sort_rows(rows);
  {
    std::ofstream sorted(out, std::ios::trunc);
    sorted << csv_header() << "\n";
    for (const auto& row : rows) sorted << row << "\n";
  }
  std::map<std::string, int> labels;
  for (const auto& row : rows) {
    std::stringstream in(row);
    std::string field;
    for (int i = 0; i < 4; ++i) std::getline(in, field, ',');
    ++labels[field];
  }
  std::printf(
      "affordance_trials: %d trials run in %.1f s on %zu instance(s), %.0f trials/min, "
      "%.1f s of sim time (%.1fx real time); %zu rows in %s:",
      done, wall, attached.empty() ? static_cast<size_t>(instances) : attached.size(),
      wall > 0 ? done / wall * 60 : 0.0, sim_seconds, wall > 0 ? sim_seconds / wall : 0.0,
      rows.size(), out.c_str());
  for (const auto& [label, count] : labels) std::printf(" %s %d", label.c_str(), count);
  std::printf("\n");
  if (repeat > 1) {
    std::printf("affordance_trials: repeats identical: %d of %d\n", done - mismatches, done);
  }
  if (bench) {
    std::printf("trials_per_minute.%s.k%zu %.1f trials/min\n", name(*affordance),
                attached.empty() ? static_cast<size_t>(instances) : attached.size(),
                wall > 0 ? done / wall * 60 : 0.0);
    std::printf("sim_time_per_trial.%s %.3f s\n", name(*affordance),
                done ? sim_seconds / done : 0.0);
  }
  if (summary.lost_instances > 0)
    std::printf("affordance_trials: %d instance(s) lost; their trials ran elsewhere\n",
                summary.lost_instances);
  if (!summary.not_run.empty() || summary.failed > 0) {
    std::printf(
        "affordance_trials: %zu trials not run (every instance lost), %d refused; run the "
        "same command again to resume\n",
        summary.not_run.size(), summary.failed);
    return 1;
  }
  if (mismatches > 0) return 3;
  return 0;
}
