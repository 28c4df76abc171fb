#include "macsim_options.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include "macsim/dds/command_line.h"
#include "macsim/dds/data_files.h"
#include "macsim/dds/log.h"
#include "macsim/dds/wire.h"
#include "macsim/render/camera_modes.h"
#include "simulation/session_compare.h"

namespace macsim::program {

std::string world_summary(const macsim::WorldSpec& spec) {
  std::map<std::string, int> kinds;
  int portable = 0;
  for (const auto& o : spec.objects) {
    portable += o.portable ? 1 : 0;
    static const char* names[] = {"objects",          "walls",       "ramps",      "switch bases",
                                  "switch platforms", "door frames", "door leaves"};
    ++kinds[names[static_cast<int>(o.kind)]];
  }
  std::vector<std::string> counts, robots;
  for (const auto& [kind, count] : kinds) counts.push_back(fmt::format("{} {}", count, kind));
  for (const auto& r : spec.robots) robots.push_back(fmt::format(" [{}: {}]", r.name, r.type));
  return fmt::format(
      "world '{}' from {}: {} objects ({} portable, {} fixed; {}), {} doors, {} robots{}, step "
      "{:g} "
      "ms",
      spec.name, spec.file, spec.objects.size(), portable, spec.objects.size() - portable,
      fmt::join(counts, ", "), spec.doors.size(), spec.robots.size(), fmt::join(robots, ""),
      spec.physics.step * 1e3);
}

namespace {

/// read_session(), refusing at once a session whose bytes were written with other wire types
/// than this build's, naming both (one that names none, format 5 and older, reads as ours).
macsim::Session read_session_of_our_types(const std::string& path,
                                          macsim::SessionRead read = macsim::SessionRead::Whole) {
  macsim::Session session = macsim::read_session(path, read);
  const std::string& recorded = session.header.wire_types;
  const std::string_view ours = macsim::dds::session_wire_types();
  if (!recorded.empty() && recorded != ours) {
    throw macsim::SessionFileError(fmt::format(
        "{}: recorded with wire types {}, this macsim's are {}: the IDL changed since, and its "
        "requests would not decode as they were written (use the macsim that recorded it)",
        path, recorded, ours));
  }
  return session;
}

/// The world, files and settings of the session read into `o` (`doing`: "replaying",
/// "resuming"), warning of command-line options it overrides.
std::optional<int> take_session_settings(Options& o, const char* doing) {
  const auto& header = o.session->header;
  if (header.self_contained) {
    // Everything from the session: its files (never the disk's) and its settings.
    if (!o.world_file.empty() && o.world_file != header.world_file) {
      macsim::log::warn("macsim: --world {} ignored: the session holds its world, {}", o.world_file,
                        header.world_file);
    }
    o.world_file = header.world_file;
    o.seed = static_cast<int>(header.seed);
    o.keep_overlaps = !header.overlaps_parted;
    o.strict = header.strict;
    o.max_import_depth = int(std::min<std::size_t>(header.limits.max_import_depth, INT_MAX));
    o.max_imported_files = int(std::min<std::size_t>(header.limits.max_imported_files, INT_MAX));
    o.max_objects = int(std::min<std::size_t>(header.limits.max_objects, INT_MAX));
    o.max_snapshots = int(std::min<std::size_t>(header.snapshot_limits.max_count, INT_MAX));
    o.max_snapshot_bytes = std::to_string(header.snapshot_limits.max_bytes);
    o.session_files = std::make_shared<macsim::MemoryFiles>();
    macsim::embed_first_files(*o.session, *o.session_files);
  } else if (!o.world_file.empty() && o.world_file != header.world_file) {
    macsim::log::warn("macsim: {} on --world {}, not the session's {}", doing, o.world_file,
                      header.world_file);
  }
  if (o.seed != -1 && o.seed != header.seed) {
    macsim::log::warn("macsim: {} with --seed {}, not the session's {}", doing, o.seed,
                      header.seed);
  }
  if (o.world_file.empty()) o.world_file = header.world_file;
  if (o.seed == -1) o.seed = static_cast<int>(header.seed);
  // Objects started inside each other are parted or kept as they were when it was recorded.
  if (!header.overlaps_parted) {
    o.keep_overlaps = true;
  } else if (o.keep_overlaps || o.strict) {
    macsim::log::warn(
        "macsim: {} with {}, but the session parted objects that started "
        "inside each other",
        doing, o.strict ? "--strict" : "--keep-overlaps");
  }
  return std::nullopt;
}

/// macsim --compare A B: 0 the same run, 1 they part (said where), 2 a usage or file error.
int compare_sessions(const Options& o) {
  if (o.arguments.size() != 1) {
    macsim::log::error("macsim: --compare A B takes two session files");
    return 2;
  }
  const std::string& a = o.compare;
  const std::string& b = o.arguments.front();
  std::optional<macsim::Session> sa, sb;
  try {
    sa = read_session_of_our_types(a);
    sb = read_session_of_our_types(b);
  } catch (const macsim::SessionFileError& e) {
    macsim::log::error("macsim: --compare: {}", e.what());
    return 2;
  }
  if (const auto part = macsim::first_difference(*sa, *sb)) {
    std::cout << "macsim: " << a << " and " << b << " part at " << *part << std::endl;
    return 1;
  }
  std::cout << "macsim: " << a << " and " << b << " are the same run: " << sa->commands.size()
            << " command records, " << sa->requests.size() << " request records, "
            << sa->hashes.size() << " state hashes, " << sa->steps << " steps" << std::endl;
  return 0;
}

/// The options of the world, the DDS participant and the pace.
void declare_run_options(macsim::dds::CommandLine& cli, Options& o) {
  cli.option("world", "FILE",
             "world file to load (required); a name not found from here is looked up among the "
             "installed worlds (share/macsim/worlds beside bin/), e.g. DemoWorld_v1.xml",
             &o.world_file);
  cli.participant_options(&o.participant);
  cli.flag("realtime", "step in real time (the default, same as --rtf 1)", &o.realtime);
  cli.option("rtf", "X", "real-time factor: sim seconds per wall second (default 1)", &o.rtf);
  cli.flag("as-fast-as-possible", "step without waiting for the wall clock",
           &o.as_fast_as_possible);
  cli.flag("paused", "start paused (run, pause and step with simulation requests)", &o.paused);
  cli.flag("lockstep", "step only when a controller asks (SIM_STEP requests); implies --paused",
           &o.lockstep);
  cli.option("duration", "SECONDS", "stop after this much sim time (default: run until SIGINT)",
             &o.duration);
  cli.option("status", "SECONDS", "print each robot's ground-truth pose every SECONDS of wall time",
             &o.status_period);
}

/// The options of what is rendered: snapshots, pictures, cameras, the viewer.
void declare_view_options(macsim::dds::CommandLine& cli, Options& o) {
  cli.repeated_option(
      "snapshot", "MODE:FILE.png",
      "render a camera mode (MouseOnly, MouseKeyboard, FixedFollow, Follow, "
      "Inside, LeftCamera, RightCamera, Manual, Chase) offscreen after the world settled, "
      "write the PNG, exit",
      &o.snapshots);
  cli.option("settle", "SECONDS", "sim time to let the world settle before --snapshot (default 1)",
             &o.settle);
  cli.size_option("snapshot-size", "WxH",
                  "image size of --snapshot and --pictures (default 640x480)",
                  &o.snapshot_size.width, &o.snapshot_size.height);
  cli.option("pictures", "DIR",
             "serve overview pictures: a PictureRequest renders a camera mode offscreen to "
             "DIR/<name>.png (default: off)",
             &o.pictures);
  cli.option("cameras", "WxH|off",
             "render and publish each robot's stereo cameras at this size (default 320x240)",
             &o.cameras);
  cli.option("camera-rate", "HZ", "camera frames per second of sim time (default 15)",
             &o.camera_rate);
  cli.flag("robot-frames",
           "prefix every frame id with the robot's name (kurt/odom, kurt/base_link): several "
           "robots in one TF tree",
           &o.robot_frames);
  cli.flag("cmd-vel-stamped",
           "take cmd_vel as geometry_msgs/TwistStamped (Nav2 from ROS 2 Kilted on), not Twist",
           &o.cmd_vel_stamped);
  cli.flag("viewer", "open a window on the world (needs an X display)", &o.viewer);
  cli.option("camera-mode", "MODE", "the window's first camera mode (default MouseKeyboard)",
             &o.camera_mode);
  cli.option("viewer-screenshot", "FILE.png", "write the window's image after 1 s",
             &o.viewer_screenshot);
}

/// The options of how a world is taken: validated, strict, overlaps kept, varied by a seed.
void declare_world_options(macsim::dds::CommandLine& cli, Options& o) {
  cli.flag("validate", "load the world, print a summary and exit", &o.validate);
  cli.flag("strict",
           "refuse a world whose objects start inside each other (exit 1), also when a request "
           "loads it; without it they are warnings",
           &o.strict);
  cli.flag("keep-overlaps",
           "leave objects and robots that start deeply inside each other where the world file "
           "puts them, for the physics to push apart (default: moved apart on load, warned)",
           &o.keep_overlaps);
  cli.option("seed", "N",
             "vary the world's layout by this seed (0 or more) as its <VARIATION> says: the "
             "same seed, the same layout (default: as written)",
             &o.seed);
}

/// The caps on what a world and its requests may make the simulator hold, and the data roots.
void declare_limit_options(macsim::dds::CommandLine& cli, Options& o) {
  cli.option("max-objects", "N",
             "refuse a world of more objects (default " + std::to_string(o.max_objects) + ")",
             &o.max_objects);
  cli.option("max-import-depth", "N",
             "refuse imports nested deeper (default " + std::to_string(o.max_import_depth) + ")",
             &o.max_import_depth);
  cli.option("max-imported-files", "N",
             "refuse a world importing more files in all (default " +
                 std::to_string(o.max_imported_files) + ")",
             &o.max_imported_files);
  cli.repeated_option(
      "data-path", "DIR",
      "let requests name files (worlds, imports, textures, spawns) under DIR too; without it "
      "only the world's folder and the shipped worlds are read (repeatable)",
      &o.data_paths);
  cli.option("max-snapshots", "N",
             "keep at most N named snapshots; saving a new name beyond is refused "
             "(ERR_LIMIT_REACHED) (default " +
                 std::to_string(o.max_snapshots) + ")",
             &o.max_snapshots);
  cli.option("max-snapshot-bytes", "BYTES",
             "keep named snapshots of at most this many bytes in all (default " +
                 o.max_snapshot_bytes + ", 256 MiB)",
             &o.max_snapshot_bytes);
  cli.option("max-pictures", "N",
             "write at most N distinct picture files per run (a name written before may be "
             "written again) (default " +
                 std::to_string(o.max_pictures) + ")",
             &o.max_pictures);
  cli.option("max-queued-commands", "N",
             "hold at most N requests and robot commands waiting for the simulation thread; "
             "a request beyond is refused (ERR_LIMIT_REACHED), a robot command dropped and "
             "counted (default " +
                 std::to_string(o.max_queued_commands) + ")",
             &o.max_queued_commands);
  cli.option("command-wait", "SECONDS",
             "a step request waits this long (wall time) for each robot command it names "
             "(commands_sent: its client's last command of each writer), then is refused "
             "(ERR_COMMANDS_MISSING, naming the writer and sample) (default " +
                 fmt::format("{:g}", o.command_wait) + ")",
             &o.command_wait);
}

/// The options of sessions: recorded, replayed, resumed, extracted, compared.
void declare_session_options(macsim::dds::CommandLine& cli, Options& o) {
  cli.option("record-session", "FILE",
             "write every command that reaches the world (with its step), the state hash every "
             "--session-hash-every steps, every file the run reads (world, imports, textures, "
             "worlds loaded later) and the settings that change results to FILE, as the run "
             "goes; --replay runs it again from that file alone",
             &o.record_session);
  cli.option("session-hash-every", "N",
             "steps between two hashes of a recorded session (default 100)", &o.session_hash_every);
  cli.option("replay", "FILE",
             "replay a recorded session without DDS: its world, its commands at their steps; "
             "checks every hash and exits 0 when all are equal, 1 at the first step that differs; "
             "the world and settings are the session's (its files are read from it, never from "
             "the disk)",
             &o.replay);
  cli.option("resume", "FILE",
             "carry on a session a killed (or stopped) macsim was recording to FILE: rebuild its "
             "world from it, run it to its last whole record, serve on and record on to FILE; "
             "with no session at FILE yet, record a new one there (as --record-session)",
             &o.resume);
  cli.option("kill-at-step", "N",
             "for tests of --resume: the process kills itself (SIGKILL, as a kill from outside "
             "would) once the run has taken N steps in all, a kill point that does not depend on "
             "timing (default 0: never)",
             &o.kill_at_step);
  cli.option("extract", "DIR",
             "with --replay: write the files the session holds under DIR instead of replaying",
             &o.extract);
  cli.option("compare", "A B",
             "read the sessions A and B and exit 0 when they are the same run (every command, "
             "request, state hash and file alike; the clients' identities and DDS writers taken "
             "as the same when they first appear in the same order, the world file's path "
             "aside), else 1, naming the first record where they part",
             &o.compare);
  cli.arguments("[B of --compare A B]", &o.arguments);
}

/// --kill-at-step, --session-hash-every, --resume and --replay checked; the session to resume or
/// replay read into `o`, its settings taken.
std::optional<int> take_session_options(Options& o) {
  if (o.kill_at_step < 0) {
    macsim::log::error("macsim: --kill-at-step takes a step count, 1 or more (0: never)");
    return 2;
  }
  if (o.session_hash_every < 1) {
    macsim::log::error("macsim: --session-hash-every must be at least 1");
    return 2;
  }
  if (!o.resume.empty() && (!o.replay.empty() || !o.record_session.empty())) {
    macsim::log::error(
        "macsim: --resume FILE records to FILE: it goes with neither --replay nor "
        "--record-session");
    return 2;
  }
  if (!o.resume.empty()) {
    std::error_code error;
    if (std::filesystem::file_size(o.resume, error) > 0 && !error) {
      try {
        o.session = read_session_of_our_types(o.resume, macsim::SessionRead::UpToLastWholeRecord);
      } catch (const macsim::SessionFileError& e) {
        macsim::log::error("macsim: --resume: {}", e.what());
        return 2;
      }
      if (!o.session->header.self_contained) {
        macsim::log::error(
            "macsim: --resume: {} is a session of format version 3 or older, which does not "
            "hold its files",
            o.resume);
        return 2;
      }
      if (o.session->version < macsim::kSessionFormatVersion) {
        // Its requests' bytes are of types it does not name, and this macsim would append
        // records of a newer format to it.
        macsim::log::error(
            "macsim: --resume: {} is a session of format version {}, written before sessions "
            "named their wire types: this macsim cannot go on with it (macsim --replay still "
            "reads it)",
            o.resume, o.session->version);
        return 2;
      }
      if (auto code = take_session_settings(o, "resuming")) return code;
    } else {
      macsim::log::info("macsim: no session at {} yet: recording a new one", o.resume);
      o.record_session = o.resume;  // nothing to resume yet: a new session
    }
  }
  if (!o.replay.empty()) {
    try {
      o.session = read_session_of_our_types(o.replay);
    } catch (const macsim::SessionFileError& e) {
      macsim::log::error("macsim: --replay: {}", e.what());
      return 2;
    }
    if (auto code = take_session_settings(o, "replaying")) return code;
  }
  return std::nullopt;
}

/// The caps on snapshots, pictures, queued commands, objects and imports, and --command-wait,
/// checked and taken.
std::optional<int> take_limits(Options& o) {
  {
    unsigned long long bytes = 0;
    const std::string& text = o.max_snapshot_bytes;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), bytes);
    if (error != std::errc() || end != text.data() + text.size() || o.max_snapshots < 1 ||
        o.max_pictures < 1) {
      macsim::log::error(
          "macsim: --max-snapshots and --max-pictures must be at least 1, --max-snapshot-bytes "
          "a count of bytes; got '{}'",
          text);
      return 2;
    }
    o.snapshot_limits = {std::size_t(o.max_snapshots), std::size_t(bytes)};
  }
  if (!(o.command_wait > 0 && o.command_wait <= 3600)) {
    macsim::log::error("macsim: --command-wait must be more than 0 and at most 3600 seconds");
    return 2;
  }
  if (o.max_objects < 1 || o.max_import_depth < 1 || o.max_imported_files < 1 ||
      o.max_queued_commands < 1) {
    macsim::log::error(
        "macsim: --max-objects, --max-import-depth, --max-imported-files and "
        "--max-queued-commands must be at least 1");
    return 2;
  }
  return std::nullopt;
}

/// The world (required; an installed one found by its name), the seed and the pace, checked.
std::optional<int> take_world_and_pace(Options& o) {
  if (o.world_file.empty()) {
    macsim::log::error("macsim: --world FILE is required (see --help)");
    return 2;
  }
  if (const auto installed = macsim::dds::data_file("worlds/" + o.world_file);
      !o.session_files && !std::filesystem::exists(o.world_file) &&
      std::filesystem::path(o.world_file).is_relative() && std::filesystem::exists(installed)) {
    o.world_file = installed;
  }
  if (o.seed < -1) {
    macsim::log::error("macsim: --seed must be 0 or more, got {}", o.seed);
    return 2;
  }
  if (!(o.rtf >= macsim::kMinRealTimeFactor) || !std::isfinite(o.rtf) || !(o.duration >= 0.0) ||
      !(o.status_period >= 0.0)) {
    macsim::log::error("macsim: --rtf must be at least {}, --duration and --status not negative",
                       macsim::kMinRealTimeFactor);
    return 2;
  }
  if (o.realtime) o.rtf = 1.0;
  return std::nullopt;
}

}  // namespace

std::optional<int> parse_options(int argc, char** argv, Options& o) {
  macsim::dds::CommandLine cli("macsim",
                               "Loads a MACSim world, steps its physics and serves it over DDS.");
  for (auto declare : {declare_run_options, declare_view_options, declare_world_options,
                       declare_limit_options, declare_session_options}) {
    declare(cli, o);
  }
  if (auto code = cli.parse(argc, argv)) return code;
  if (!o.compare.empty()) return compare_sessions(o);
  if (!o.arguments.empty()) {
    macsim::log::error("macsim: unexpected argument '{}' (see --help)", o.arguments.front());
    return 2;
  }
  for (auto take : {take_session_options, take_limits, take_world_and_pace}) {
    if (auto code = take(o)) return code;
  }
  return std::nullopt;
}

std::shared_ptr<const macsim::DataRoots> data_roots(const Options& o) {
  if (o.session_files) return macsim::DataRoots::only(o.session_files);
  std::vector<std::string> folders;
  std::error_code error;
  folders.push_back(std::filesystem::absolute(o.world_file, error).parent_path().string());
  if (const auto shipped = macsim::dds::data_file("worlds");
      std::filesystem::is_directory(shipped, error)) {
    folders.push_back(shipped);
  }
  folders.insert(folders.end(), o.data_paths.begin(), o.data_paths.end());
  return std::make_shared<const macsim::DataRoots>(folders);
}

const macsim::WorldFiles& world_files(const Options& o) {
  return o.session_files ? *o.session_files : macsim::disk_files();
}

macsim::SessionHeader session_header(const Options& o, bool overlaps_parted) {
  macsim::SessionHeader header;
  header.world_file = o.world_file;
  header.seed = o.seed;
  header.hash_every = uint64_t(o.session_hash_every);
  header.overlaps_parted = overlaps_parted;
  header.strict = o.strict;
  header.limits = o.limits();
  header.snapshot_limits = o.snapshot_limits;
  header.wire_types = std::string(macsim::dds::session_wire_types());
  return header;
}

int extract_session_files(const macsim::Session& session, const std::string& dir) {
  namespace fs = std::filesystem;
  if (!session.header.self_contained) {
    macsim::log::error(
        "macsim: --extract: {} is a session of format version 3 or older: it holds "
        "no files",
        session.header.world_file);
    return 2;
  }
  std::error_code error;
  for (const auto& file : session.files) {
    // The path as the run asked for it, made relative: no root, and '..' spelled "up".
    fs::path relative;
    for (const auto& part : fs::path(file.path).lexically_normal().relative_path()) {
      relative /= part == ".." ? fs::path("up") : part;
    }
    const fs::path target = fs::path(dir) / relative;
    fs::create_directories(target.parent_path(), error);
    std::ofstream out(target, std::ios::binary | std::ios::trunc);
    out.write(file.bytes.data(), std::streamsize(file.bytes.size()));
    out.close();
    if (error || !out) {
      macsim::log::error("macsim: --extract: cannot write {}", target.string());
      return 2;
    }
    std::printf("%s (%zu bytes, read as %s)\n", target.string().c_str(), file.bytes.size(),
                file.path.c_str());
  }
  return 0;
}

}  // namespace macsim::program
