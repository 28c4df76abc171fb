// macsim: loads a world, steps it and serves it over Fast DDS. This file reads the command
// line, loads the world and picks how it runs (macsim_runs.h).
#include <fmt/ranges.h>

#include <iostream>
#include <memory>
#include <stdexcept>

#include "macsim/dds/log.h"
#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/session.h"
#include "macsim/sim_core/world_loader.h"
#include "macsim/sim_core/world_overlaps.h"
#include "macsim/sim_core/world_variation.h"
#include "macsim_options.h"
#include "macsim_runs.h"

using namespace macsim::program;

int main(int argc, char** argv) {
  Options o;
  if (auto code = parse_options(argc, argv, o)) return *code;
  // sim_core's messages (the loader's, the runner's, the cameras', the session writer's) in
  // this program's log, with its levels, --quiet and --log-timestamps.
  macsim::set_log_sink([](macsim::LogLevel level, const std::string& message) {
    constexpr macsim::log::Level kLevels[] = {macsim::log::Level::debug, macsim::log::Level::info,
                                              macsim::log::Level::warn, macsim::log::Level::error};
    macsim::log::write(kLevels[static_cast<int>(level)], message);
  });
  if (o.session && !o.extract.empty()) return extract_session_files(*o.session, o.extract);
  if (!o.extract.empty()) {
    macsim::log::error("macsim: --extract DIR goes with --replay FILE");
    return 2;
  }
  // A recorded run embeds every file it reads, from the first world on: those read before the
  // session file is opened wait here.
  std::vector<std::pair<std::string, std::string>> first_files;
  const macsim::WatchedFiles watched(
      world_files(o), [&first_files](const std::string& path, const std::string& bytes) {
        first_files.emplace_back(path, bytes);
      });
  std::unique_ptr<macsim::Runner> runner;
  try {
    macsim::LoadOptions load;
    load.limits = o.limits();
    load.files = &watched;
    auto spec = macsim::load_world_file(o.world_file, load);
    // What --validate asks for goes to standard output; otherwise it is a diagnostic.
    if (o.validate) {
      std::cout << world_summary(spec) << std::endl;
    } else {
      macsim::log::info("{}", world_summary(spec));
    }
    if (o.seed >= 0) {
      const auto moved = macsim::vary_world(spec, static_cast<uint32_t>(o.seed));
      macsim::log::info("macsim: layout of seed {}:\n  {}", o.seed, fmt::join(moved, "\n  "));
    }
    // Heaps of things started inside each other are parted before the first step.
    const bool part = !o.strict && !o.keep_overlaps;
    if (part) {
      for (const auto& line : macsim::part_overlaps(spec)) macsim::log::warn("{}", line);
    }
    macsim::RunSettings settings;
    settings.part_overlaps = part;
    settings.paused = o.paused || o.lockstep;
    settings.real_time_factor = o.as_fast_as_possible ? 0.0 : o.rtf;
    settings.refuse_overlaps = o.strict;  // for worlds loaded later by a request
    settings.max_queued_commands = std::size_t(o.max_queued_commands);
    settings.command_wait = o.command_wait;
    runner = std::make_unique<macsim::Runner>(std::move(spec), settings);
    const auto overlaps = macsim::admit_overlaps(runner->world(), o.strict);
    if (o.validate) {
      std::cout << "macsim: "
                << (overlaps.empty() ? "no objects start inside each other"
                                     : macsim::overlap_error(overlaps, 0) + " (warnings above)")
                << std::endl;
    }
  } catch (const macsim::WorldFileError& e) {
    macsim::log::error("macsim: {}", e.what());
    return 1;
  }
  try {
    runner->set_data_roots(data_roots(o));
  } catch (const std::invalid_argument& e) {
    macsim::log::error("macsim: --data-path: {}", e.what());
    return 2;
  }
  runner->snapshots().set_limits(o.snapshot_limits);
  runner->set_max_objects(std::size_t(o.max_objects));
  if (o.validate) return 0;
  if (!o.snapshots.empty()) {
    return write_snapshots(*runner, o.snapshots, o.settle, o.snapshot_size);
  }
  if (o.session && !o.resume.empty()) return resume(*runner, o);
  if (o.session) return replay(*runner, o);
  std::shared_ptr<macsim::SessionWriter> session;
  if (!o.record_session.empty()) {
    try {
      session = std::make_shared<macsim::SessionWriter>(
          o.record_session, session_header(o, runner->settings().part_overlaps));
      for (const auto& [path, bytes] : first_files) session->file(path, bytes);
      // Every file a request reads from now on goes into the session as it is read.
      runner->set_data_roots(runner->data_roots().watched(
          [writer = session](const std::string& path, const std::string& bytes) {
            writer->file(path, bytes);
          }));
      runner->record(session);
    } catch (const macsim::SessionFileError& e) {
      macsim::log::error("macsim: --record-session: {}", e.what());
      return 2;
    }
  }

  return serve(*runner, o, session.get());
}
