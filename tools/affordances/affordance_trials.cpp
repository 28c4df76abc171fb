// affordance_trials: runs lift, push or climb trials on lock-step simulators and writes one CSV
// row per trial: what the robot perceived, the object's true properties, the label measured on
// the world state, sim and wall time. Trials run on K simulators at once; a run that was killed
// resumes where it stopped. A run may take one shard of the seeds (--shard I/N, one task of a
// cluster job array); `affordance_trials merge` joins the shards' files and reports what is
// missing.
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "csv_writer.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/data_files.h"
#include "macsim/dds/log.h"
#include "trial_pool.h"

namespace {

using namespace affordances;
namespace log = macsim::log;
using Clock = std::chrono::steady_clock;

/// One updating line on a terminal, a plain line every 10 s otherwise (a cluster task's output
/// file); `prefix` names the shard ("shard 2/4: ").
class Progress {
 public:
  Progress(int total, int already, std::string prefix)
      : total_(total), already_(already), tty_(isatty(2)), prefix_(std::move(prefix)) {}
  void update(int done, bool last = false) {
    const auto now = Clock::now();
    if (!last && !tty_ && now - printed_ < std::chrono::seconds(10)) return;
    if (!last && tty_ && now - printed_ < std::chrono::milliseconds(200)) return;
    printed_ = now;
    const double minutes = std::chrono::duration<double>(now - start_).count() / 60.0;
    const double rate = minutes > 0 ? done / minutes : 0.0;
    const int left = total_ - already_ - done;
    char line[200];
    std::snprintf(line, sizeof line, "%strials %d/%d, %.0f trials/min, ETA %s", prefix_.c_str(),
                  already_ + done, total_, rate, rate > 0 ? eta(left / rate * 60).c_str() : "-");
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
  std::string prefix_;
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

/// The row's key: affordance, generator, seed (the first three columns), as trial_key().
std::string key_of(const std::string& row) {
  auto fields = csv::split(row);
  fields.resize(3);
  return csv::join(fields);
}

/// Rows sorted by affordance, generator and seed.
void sort_rows(std::vector<std::string>& rows) {
  using Key = std::tuple<std::string, std::string, unsigned long long>;
  std::vector<std::pair<Key, std::string>> keyed;
  keyed.reserve(rows.size());
  for (auto& row : rows) {
    auto fields = csv::split(row);
    fields.resize(3);
    keyed.emplace_back(Key{fields[0], fields[1], std::stoull(fields[2])}, std::move(row));
  }
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = std::move(keyed[i].second);
}

/// A row without its last two columns (instance, wall time): what must repeat bit for bit.
std::string result_part(const std::string& row) {
  auto fields = csv::split(row);
  fields.resize(fields.size() < 2 ? 0 : fields.size() - 2);
  return csv::join(fields);
}

/// A whole number in `text` (nothing else), or nullopt.
template <class Number>
std::optional<Number> whole_number(const std::string& text) {
  Number value{};
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

/// One share of the trials: shard `index` of `count` (--shard I/N).
struct Shard {
  int index = 0, count = 1;
};

/// "I/N" with 0 <= I < N, or nullopt.
std::optional<Shard> parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) return std::nullopt;
  const auto index = whole_number<int>(text.substr(0, slash));
  const auto count = whole_number<int>(text.substr(slash + 1));
  if (!index || !count || *count < 1 || *index < 0 || *index >= *count) return std::nullopt;
  return Shard{*index, *count};
}

/// Shard I of N holds trials [I*T/N, (I+1)*T/N) of T: contiguous blocks whose sizes differ by
/// at most one, together every trial once.
std::pair<int, int> shard_trials(const Shard& shard, int trials) {
  auto at = [&](int64_t i) { return static_cast<int>(i * trials / shard.count); };
  return {at(shard.index), at(shard.index + 1)};
}

/// "A-B" (or "A" for one seed, "-" for none).
std::string seed_range(uint64_t first, uint64_t end) {
  if (end <= first) return "-";
  if (end == first + 1) return std::to_string(first);
  return std::to_string(first) + "-" + std::to_string(end - 1);
}

/// `affordance_trials merge`: joins the files of shards (or of any runs) into one, sorted by
/// affordance, generator and seed; refuses files of other columns (2) and rows of one trial
/// that differ (3); reports the seeds missing from S..S+T-1, shard by shard (1).
int merge(int argc, char** argv) {
  std::string out, affordance_name, generator_name, seed_text = "1";
  int trials = 0, shards = 1;
  std::vector<std::string> inputs;
  macsim::dds::CommandLine cli(
      "affordance_trials merge",
      "Joins the CSV files of affordance_trials runs (the shards of a job array, --shard I/N) "
      "into one sorted by affordance, generator and seed, as one run of every seed writes it. "
      "Rows of the same trial must agree in every column but the last two (instance, wall "
      "time); one of identical rows is kept. With --trials it reports, shard by shard, the "
      "seeds done and missing of S..S+T-1 (the same blocks as --shard); without, the gaps "
      "between the smallest and the largest seed found. No DDS: it only reads and writes "
      "files.\n"
      "OUT is written (through a temporary file, so an input may be OUT) unless exit is 2 or 3.\n"
      "Exit 0: every expected seed has its row; 1: seeds missing (listed; OUT holds the rows "
      "there are); 2: usage, or an input that cannot be read or has other columns than this "
      "version writes; 3: two rows of one trial differ (both files and the seed named).");
  cli.option("out", "OUT.csv", "the merged file (required)", &out);
  cli.option("seed", "S", "seed of the first trial of the run (default 1)", &seed_text);
  cli.option("trials", "T", "trials of the whole run: seeds S..S+T-1 are expected", &trials);
  cli.option("shards", "N", "the run's shards, for the report per shard (default 1)", &shards);
  cli.option("affordance", "lift|push|climb|stack|traverse",
             "the affordance expected (default: those of the rows; lift when there are none)",
             &affordance_name);
  cli.option("generator", "material|figure11|balanced",
             "the generator expected (default: those of the rows; material when there are none)",
             &generator_name);
  cli.arguments("IN.csv...", &inputs);
  if (auto code = cli.parse(argc, argv)) return *code;

  auto usage = [](const std::string& message) {
    log::error("affordance_trials merge: {} (see affordance_trials merge --help)", message);
    return 2;
  };
  const auto first_seed = whole_number<uint64_t>(seed_text);
  if (out.empty()) return usage("say where the merged rows go: --out OUT.csv");
  if (inputs.empty()) return usage("name the files to merge: IN.csv...");
  if (!first_seed) return usage("--seed takes a whole number >= 0: '" + seed_text + "'");
  if (trials < 0 || shards < 1) return usage("--trials must be positive, --shards at least 1");
  if (shards > 1 && trials == 0) return usage("--shards needs --trials (the run's trials)");
  if (trials > 0 && shards > trials)
    return usage("--shards " + std::to_string(shards) + " is more than --trials " +
                 std::to_string(trials));
  if (!affordance_name.empty() && !affordance_from_name(affordance_name))
    return usage("unknown --affordance '" + affordance_name +
                 "' (lift, push, climb, stack, traverse)");
  if (!generator_name.empty() && !generator_from_name(generator_name))
    return usage("unknown --generator '" + generator_name + "' (material, figure11, balanced)");

  // Every row by its trial (affordance, generator, seed), with the file it came from.
  struct Kept {
    std::string row, file;
  };
  std::map<std::tuple<std::string, std::string, uint64_t>, Kept> kept;
  int read = 0, identical = 0, conflicts = 0;
  std::string header;  // the first file's; every other must have the same
  for (const auto& path : inputs) {
    if (std::filesystem::is_regular_file(path) && std::filesystem::file_size(path) == 0) {
      // A task killed before it wrote anything: no rows (its seeds are reported missing).
      log::warn("affordance_trials merge: {} is empty (no rows)", path);
      continue;
    }
    CsvTable table;
    try {
      if (!std::filesystem::is_regular_file(path))
        throw std::runtime_error(path + ": no such file");
      table = read_csv(path);
    } catch (const std::exception& e) {
      log::error("affordance_trials merge: {}", e.what());
      return 2;
    }
    // One header for every file: that of an affordance this version writes.
    const std::string columns = csv::join(table.columns);
    bool known = false;
    for (auto a : {Affordance::Lift, Affordance::Stack, Affordance::Traverse})
      known = known || columns == csv_header(a);
    if (!affordance_name.empty())  // the columns of the affordance named
      known = columns == csv_header(*affordance_from_name(affordance_name));
    if (!known || (!header.empty() && columns != header)) {
      log::error("affordance_trials merge: {}{} (its header: {}...)", path,
                 known ? " has other columns than the files before it"
                 : affordance_name.empty()
                     ? " has other columns than this version writes"
                     : " has other columns than " + affordance_name + " rows (--affordance)",
                 columns.substr(0, 120));
      return 2;
    }
    header = columns;
    for (std::size_t i = 0; i < table.rows.size(); ++i) {
      const std::string row = csv::join(table.rows[i]);
      const auto seed = whole_number<uint64_t>(table.rows[i][2]);
      if (!seed) {
        log::error("affordance_trials merge: {}: row {} has no whole-number seed: '{}'", path,
                   i + 1, table.rows[i][2]);
        return 2;
      }
      ++read;
      const auto key = std::make_tuple(table.rows[i][0], table.rows[i][1], *seed);
      auto [at, inserted] = kept.emplace(key, Kept{row, path});
      if (inserted) continue;
      if (result_part(at->second.row) == result_part(row)) {
        ++identical;
        continue;
      }
      ++conflicts;
      log::error("affordance_trials merge: {},{} seed {} differs between {} and {}:\n  {}\n  {}",
                 table.rows[i][0], table.rows[i][1], *seed, at->second.file, path,
                 result_part(at->second.row), result_part(row));
    }
  }
  if (conflicts > 0) {
    log::error(
        "affordance_trials merge: {} row(s) differ from another row of the same trial; nothing "
        "written (a trial gives the same row wherever it runs: were the files made by different "
        "versions or worlds?)",
        conflicts);
    return 3;
  }

  // The expected trials: for each affordance and generator named or found, seeds S..S+T-1.
  std::set<std::pair<std::string, std::string>> kinds;
  for (const auto& [key, row] : kept) {
    if ((affordance_name.empty() || std::get<0>(key) == affordance_name) &&
        (generator_name.empty() || std::get<1>(key) == generator_name))
      kinds.emplace(std::get<0>(key), std::get<1>(key));
  }
  if (kinds.empty())
    kinds.emplace(affordance_name.empty() ? "lift" : affordance_name,
                  generator_name.empty() ? "material" : generator_name);
  int missing_total = 0, outside = 0;
  for (const auto& [a, g] : kinds) {
    const std::string who = kinds.size() > 1 ? a + "," + g + " " : "";
    std::vector<uint64_t> seeds;  // those present, in order
    for (auto it = kept.lower_bound({a, g, 0});
         it != kept.end() && std::get<0>(it->first) == a && std::get<1>(it->first) == g; ++it)
      seeds.push_back(std::get<2>(it->first));
    auto report = [&](const std::string& title, uint64_t first, uint64_t end) {
      std::vector<uint64_t> missing;
      const auto from = std::lower_bound(seeds.begin(), seeds.end(), first);
      const auto to = std::lower_bound(seeds.begin(), seeds.end(), end);
      auto present = from;
      for (uint64_t s = first; s < end; ++s) {
        if (present != to && *present == s)
          ++present;
        else
          missing.push_back(s);
      }
      std::printf("%s%s: seeds %s, done %zu, missing %zu", who.c_str(), title.c_str(),
                  seed_range(first, end).c_str(), static_cast<size_t>(to - from), missing.size());
      if (!missing.empty()) {
        std::printf(" (");
        for (std::size_t i = 0; i < missing.size() && i < 8; ++i)
          std::printf("%s%" PRIu64, i ? " " : "", missing[i]);
        std::printf("%s)", missing.size() > 8 ? " ..." : "");
      }
      std::printf("\n");
      missing_total += static_cast<int>(missing.size());
    };
    if (trials > 0) {
      const uint64_t first = *first_seed, end = first + static_cast<uint64_t>(trials);
      for (int i = 0; i < shards; ++i) {
        const auto [begin_trial, end_trial] = shard_trials({i, shards}, trials);
        report(shards > 1 ? "shard " + std::to_string(i) : std::string("all"),
               first + static_cast<uint64_t>(begin_trial),
               first + static_cast<uint64_t>(end_trial));
      }
      for (uint64_t s : seeds) outside += s < first || s >= end;
    } else if (!seeds.empty()) {
      report("found", seeds.front(), seeds.back() + 1);
    }
  }
  if (outside > 0)
    std::printf("affordance_trials merge: %d row(s) of seeds outside %s (kept)\n", outside,
                seed_range(*first_seed, *first_seed + static_cast<uint64_t>(trials)).c_str());

  std::vector<std::string> rows;
  rows.reserve(kept.size());
  for (const auto& [key, row] : kept) rows.push_back(row.row);
  sort_rows(rows);
  const std::string temporary = out + ".merging";
  {
    std::ofstream file(temporary, std::ios::trunc);
    if (header.empty()) {
      header = csv_header(affordance_name.empty() ? Affordance::Lift
                                                  : *affordance_from_name(affordance_name));
    }
    file << header << "\n";
    for (const auto& row : rows) file << row << "\n";
    file.close();
    if (!file) {
      std::filesystem::remove(temporary);
      log::error("affordance_trials merge: cannot write {}", temporary);
      return 2;
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, out, error);
  if (error) {
    log::error("affordance_trials merge: cannot write {}: {}", out, error.message());
    return 2;
  }
  std::printf(
      "affordance_trials merge: %zu rows from %zu file(s) in %s (%d rows read, %d identical "
      "duplicate(s) kept once); %s\n",
      rows.size(), inputs.size(), out.c_str(), read, identical,
      missing_total ? (std::to_string(missing_total) + " seed(s) missing").c_str()
                    : "no seed missing");
  return missing_total ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "merge") return merge(argc - 1, argv + 1);
  macsim::dds::ParticipantOptions participant{-1, "", "affordance_trials"};
  int trials = 100, instances = 1, repeat = 1;
  double first_seed = 1, timeout = 10;
  std::string affordance_name = "lift", generator_name = "material", out, world, attach, log_dir,
              cameras = "320x240", shard_text, inputs_dir;
  double camera_rate = 1.25;
  bool hash_every_step = false, bench = false;
  macsim::dds::CommandLine cli(
      "affordance_trials",
      "Runs affordance trials on lock-step simulators: each trial resets the world, spawns an "
      "object (or a ramp) drawn from its seed, lets the robot perceive it with its cameras and "
      "laser and try the affordance, and labels the outcome from the world state. One CSV row "
      "per trial; a killed run resumes (rows already in --out are not run again).\n"
      "It starts --instances simulators on domains N, N+1, ... (--domain N is required) or uses "
      "running ones (--attach D1,D2,...: simulators already running, here or on other hosts, "
      "started as macsim --lockstep --camera-rate HZ).\n"
      "On a cluster, each task of a job array runs one shard of the seeds (--shard I/N) into a "
      "file of its own, and `affordance_trials merge --out OUT.csv [--seed S --trials T --shards "
      "N] IN.csv...` joins the files, refuses rows of one trial that differ and reports the "
      "seeds missing per shard (see affordance_trials merge --help; deploy/slurm/).\n"
      "Exit 0: every trial has its row; 1: trials are missing (every instance lost, or refused); "
      "2: usage; 3: --repeat found a trial that did not repeat bit for bit.");
  cli.participant_options(&participant);
  cli.option("affordance", "lift|push|climb|stack|traverse", "the affordance tried (default lift)",
             &affordance_name);
  cli.option("generator", "material|figure11|balanced",
             "how objects are drawn: material (liftability from mass and magnet), figure11 "
             "(heavy objects are blue) or balanced (no label of the affordance below about a "
             "fifth); default material",
             &generator_name);
  cli.option("trials", "N", "number of trials (default 100)", &trials);
  cli.option("seed", "S", "seed of the first trial; trial i has seed S+i (default 1)", &first_seed);
  cli.option("shard", "I/N",
             "run only shard I of N (0 <= I < N) of the --trials: trials [I*T/N, (I+1)*T/N), "
             "one task of a job array",
             &shard_text);
  cli.option("instances", "K", "simulators to start (default 1)", &instances);
  cli.option("attach", "D1,D2,...",
             "use lock-step simulators already running on these domains (here or on other "
             "hosts) instead of starting them",
             &attach);
  cli.option("out", "FILE.csv", "the trial rows (appended to when it exists: resume)", &out);
  cli.option("world", "FILE",
             "world of the started simulators (default worlds/affordance_trials.xml)", &world);
  cli.option("cameras", "WxH", "camera size of the started simulators (default 320x240)", &cameras);
  cli.option("camera-rate", "HZ",
             "camera rate of the simulators (default 1.25: a pair at the perception instant)",
             &camera_rate);
  cli.option("timeout", "SECONDS",
             "an instance whose participant left is lost after this long (wall time); one still "
             "matched but silent, after six times it (default 10)",
             &timeout);
  cli.option("logs", "DIR",
             "logs of the started simulators (default a fresh /tmp directory, removed after a run "
             "where no instance was lost and no trial refused)",
             &log_dir);
  cli.option("repeat", "R", "run every trial R times and check the rows are identical (default 1)",
             &repeat);
  cli.flag("hash-every-step", "the trace hash covers the state hash of every step",
           &hash_every_step);
  cli.option("keep-inputs", "DIR",
             "write what each trial perceived from (the stereo pair as PNGs, the sweep and the "
             "cloud) to DIR/<affordance>_<seed>*: its row's features can be computed again from "
             "them (macsim::affordances::load_inputs)",
             &inputs_dir);
  cli.flag("bench",
           "print trials per minute and the scoped reset's round trip as `name value unit`",
           &bench);
  if (auto code = cli.parse(argc, argv)) return *code;

  const auto affordance = affordance_from_name(affordance_name);
  const auto generator = generator_from_name(generator_name);
  const std::vector<int> attached = attach.empty() ? std::vector<int>{} : parse_domains(attach);
  const std::optional<Shard> shard = shard_text.empty() ? Shard{} : parse_shard(shard_text);
  auto usage = [](const std::string& message) {
    log::error("affordance_trials: {} (see --help)", message);
    return 2;
  };
  if (!affordance)
    return usage("unknown --affordance '" + affordance_name +
                 "' (lift, push, climb, stack, traverse)");
  if (!generator)
    return usage("unknown --generator '" + generator_name + "' (material, figure11, balanced)");
  if (out.empty()) return usage("say where the rows go: --out FILE.csv");
  if (trials < 1 || instances < 1 || instances > 32 || repeat < 1 || first_seed < 0 ||
      !(timeout > 0) || !(camera_rate > 0))
    return usage(
        "--trials, --repeat, --timeout and --camera-rate must be positive, --instances 1..32, "
        "--seed >= 0");
  if (!shard)
    return usage("--shard takes I/N with 0 <= I < N (shard I of N): '" + shard_text + "'");
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
      if (csv::join(table.columns) != csv_header(*affordance)) {
        log::error("affordance_trials: {} has other columns than this version writes", out);
        return 2;
      }
      for (const auto& fields : table.rows) {
        const std::string row = csv::join(fields);
        have.insert(key_of(row));
        rows.push_back(row);
      }
    } catch (const std::exception& e) {
      log::error("affordance_trials: {}", e.what());
      return 2;
    }
  }
  // This run's trials: all of them, or its shard's block.
  const auto [first_trial, end_trial] = shard_trials(*shard, trials);
  std::vector<TrialSpec> todo;
  const auto first = static_cast<uint64_t>(first_seed);
  int wanted = 0;
  for (int i = first_trial; i < end_trial; ++i) {
    const TrialSpec spec = make_trial(*affordance, *generator, first + static_cast<uint64_t>(i));
    ++wanted;
    if (have.count(trial_key(name(spec.affordance), name(spec.generator), spec.seed))) continue;
    for (int r = 0; r < repeat; ++r) todo.push_back(spec);
  }
  const int already = wanted - static_cast<int>(todo.size()) / repeat;
  if (already > 0) log::info("affordance_trials: {} trials already in {}", already, out);

  // The file as it stands (a row cut short by a kill is dropped), then a row per trial done.
  {
    std::ofstream file(out, std::ios::trunc);
    file << csv_header(*affordance) << "\n";
    for (const auto& row : rows) file << row << "\n";
    if (!file) {
      log::error("affordance_trials: cannot write {}", out);
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
  pool.instance.keep_inputs = !inputs_dir.empty();
  pool.instance.timeout = std::chrono::milliseconds(static_cast<int64_t>(timeout * 1000));
  const bool temporary_logs = log_dir.empty();  // removed after a run with nothing to tell
  if (temporary_logs) {
    log_dir =
        (std::filesystem::temp_directory_path() / ("affordance_trials_" + std::to_string(getpid())))
            .string();
  }
  if (!todo.empty()) std::filesystem::create_directories(log_dir);
  pool.log_dir = log_dir;

  const bool sharded = !shard_text.empty();
  const std::string shard_name =
      sharded ? "shard " + std::to_string(shard->index) + "/" + std::to_string(shard->count) : "";
  if (sharded)
    log::info("affordance_trials: {}: seeds {}, {} to run", shard_name,
              seed_range(first + static_cast<uint64_t>(first_trial),
                         first + static_cast<uint64_t>(end_trial)),
              static_cast<int>(todo.size()) / repeat);
  Progress progress(wanted * repeat, already * repeat, sharded ? shard_name + ": " : "");
  std::map<std::string, std::string> first_result;  // --repeat: the first row of each trial
  int mismatches = 0, done = 0;
  double sim_seconds = 0;
  const auto start = Clock::now();
  auto first_began = Clock::time_point::max();
  // Nothing left (a finished shard run again): no simulator is started.
  auto run = [&](const std::function<void(const TrialRecord&)>& done_one) {
    return todo.empty() ? PoolSummary{} : TrialPool(pool).run(todo, done_one);
  };
  const PoolSummary summary = run([&](const TrialRecord& record) {
    const std::string row = csv_row(record);
    const std::string key = key_of(row);
    auto [seen, inserted] = first_result.emplace(key, result_part(row));
    if (inserted) {
      file << row << "\n" << std::flush;
      rows.push_back(row);
      if (!inputs_dir.empty()) {
        macsim::affordances::save_inputs(
            record.inputs, inputs_dir,
            std::string(name(record.spec.affordance)) + "_" + std::to_string(record.spec.seed));
      }
    } else if (seen->second != result_part(row)) {
      ++mismatches;
      log::warn("\naffordance_trials: trial {} differs when repeated:\n  {}\n  {}", key,
                seen->second, result_part(row));
    }
    sim_seconds += record.sim_time;
    // When the earliest trial began: the simulators' start-up and first look came before.
    const auto began = Clock::now() - std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(record.wall_time));
    first_began = std::min(first_began, began);
    progress.update(++done);
  });
  progress.update(done, true);
  const auto end = Clock::now();
  const double wall = std::chrono::duration<double>(end - start).count();
  const double running = done ? std::chrono::duration<double>(end - first_began).count() : 0.0;

  // Sorted by seed: the same trials give the same file, however many instances ran them.
  // Written beside it and renamed over it, so a kill now (a cluster task cancelled at its end)
  // leaves the rows either as appended or sorted, never lost.
  file.close();
  sort_rows(rows);
  {
    const std::string temporary = out + ".sorting";
    std::ofstream sorted(temporary, std::ios::trunc);
    sorted << csv_header(*affordance) << "\n";
    for (const auto& row : rows) sorted << row << "\n";
    sorted.close();
    std::error_code error;
    if (sorted) std::filesystem::rename(temporary, out, error);
    if (!sorted || error) {
      std::filesystem::remove(temporary, error);
      log::warn(
          "affordance_trials: cannot write the sorted rows; {} keeps them in the order they "
          "came",
          out);
    }
  }
  std::map<std::string, int> labels;
  for (const auto& row : rows) {
    const auto fields = csv::split(row);
    ++labels[fields.size() > 3 ? fields[3] : std::string()];
  }
  std::printf(
      "affordance_trials: %s%s%d trials run in %.1f s on %zu instance(s), %.0f trials/min, "
      "%.1f s of sim time (%.1fx real time); %zu rows in %s:",
      shard_name.c_str(), sharded ? ": " : "", done, wall,
      attached.empty() ? static_cast<size_t>(instances) : attached.size(),
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
    // Without the simulators' start-up (a fixed cost of a run, not of its trials).
    std::printf("trials_per_minute_running.%s.k%zu %.1f trials/min\n", name(*affordance),
                attached.empty() ? static_cast<size_t>(instances) : attached.size(),
                running > 0 ? done / running * 60 : 0.0);
    std::printf("start_up.%s %.2f s\n", name(*affordance), wall - running);
    std::printf("sim_time_per_trial.%s %.3f s\n", name(*affordance),
                done ? sim_seconds / done : 0.0);
  }
  if (summary.reconnects > 0)
    std::printf("affordance_trials: %d reconnection(s) to a simulator lost while it still ran\n",
                summary.reconnects);
  if (summary.restarts > 0)
    std::printf(
        "affordance_trials: %d simulator(s) started again after they died; the trials "
        "under way played again from their reset\n",
        summary.restarts);
  if (summary.lost_instances > 0)
    std::printf("affordance_trials: %d instance(s) lost; their trials ran elsewhere\n",
                summary.lost_instances);
  // The logs of a run whose simulators died or were lost are kept, so that it can be understood.
  const bool clean = summary.lost_instances == 0 && summary.restarts == 0 &&
                     summary.not_run.empty() && summary.failed == 0;
  if (temporary_logs && !todo.empty()) {
    std::error_code ignored;
    if (clean)
      std::filesystem::remove_all(log_dir, ignored);
    else
      std::printf("affordance_trials: the simulators' logs are in %s\n", log_dir.c_str());
  }
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
