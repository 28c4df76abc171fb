// macsim: loads a world, steps it and serves it over Fast DDS.
#include <fmt/ranges.h>

#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "macsim/dds/command_line.h"
#include "macsim/dds/data_files.h"
#include "macsim/dds/log.h"
#include "macsim/dds/shared_memory.h"
#include "macsim/dds/topics.h"
#include "macsim/dds/wire.h"
#include "macsim/render/camera_modes.h"
#include "macsim/render/renderer.h"
#include "macsim/render/viewer.h"
#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/session.h"
#include "macsim/sim_core/world_loader.h"
#include "macsim/sim_core/world_variation.h"
#include "picture_server.h"
#include "sim_bridge.h"
#include "sim_interfaces_dispatch.h"
#include "sim_interfaces_server.h"
#include "simulation_dispatch.h"
#include "simulation_server.h"
#include "supervisor_dispatch.h"
#include "supervisor_server.h"

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) { g_stop.store(true); }

/// One line on what the world holds.
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
      "world '{}' from {}: {} objects ({} portable, {} fixed; {}), {} doors, {} robots{}, step {:g} "
      "ms",
      spec.name, spec.file, spec.objects.size(), portable, spec.objects.size() - portable,
      fmt::join(counts, ", "), spec.doors.size(), spec.robots.size(), fmt::join(robots, ""),
      spec.physics.step * 1e3);
}

void print_status(const macsim::World& world) {
  for (const auto& robot : world.robots()) {
    const macsim::Pose p = robot->base_footprint_pose();
    const Eigen::Vector3d heading = p.orientation * Eigen::Vector3d::UnitX();
    macsim::log::info("macsim: t={:7.2f} s  {} at x={:.3f} y={:.3f} yaw={:.1f} deg, speed {:.2f} m/s",
                      world.time(), robot->name(), p.position.x(), p.position.y(),
                      std::atan2(heading.y(), heading.x()) * 180.0 / M_PI,
                      robot->linear_velocity().norm());
  }
}

/// --snapshot: settle, render each requested camera mode offscreen, write the PNGs.
int write_snapshots(macsim::Runner& runner, const std::vector<std::string>& requests, double settle,
                    const macsim::render::CameraIntrinsics& intrinsics) {
  namespace render = macsim::render;
  std::vector<std::pair<render::CameraMode, std::string>> jobs;
  for (const auto& request : requests) {
    const auto colon = request.find(':');
    const auto mode = colon == std::string::npos
                          ? std::nullopt
                          : render::camera_mode_from_name(request.substr(0, colon));
    if (!mode || colon + 1 >= request.size()) {
      macsim::log::error(
          "macsim: --snapshot takes MODE:FILE.png with MODE one of MouseOnly, MouseKeyboard, "
          "FixedFollow, Follow, Inside, LeftCamera, RightCamera, Manual, Chase; got '{}'",
          request);
      return 2;
    }
    jobs.emplace_back(*mode, request.substr(colon + 1));
  }
  if (settle < 0) {
    macsim::log::error("macsim: --settle must not be negative");
    return 2;
  }
  const auto steps = static_cast<long>(std::llround(settle / runner.world().step_size()));
  for (long i = 0; i < steps; ++i) runner.step();
  try {
    render::OffscreenRenderer renderer(intrinsics.width, intrinsics.height);
    const macsim::Scene scene = macsim::capture_scene(runner.world());
    for (const auto& [mode, file] : jobs) {
      const cv::Mat image = renderer.render(scene, render::camera_pose(mode, scene), intrinsics);
      if (!cv::imwrite(file, image)) {
        macsim::log::error("macsim: cannot write '{}'", file);
        return 1;
      }
      macsim::log::info("macsim: wrote {} view to {} ({}x{}, {})", render::camera_mode_name(mode),
                        file, intrinsics.width, intrinsics.height, renderer.gl_renderer());
    }
  } catch (const render::RenderError& e) {
    macsim::log::error("macsim: cannot render offscreen: {}", e.what());
    return 1;
  }
  return 0;
}

/// What the command line asks for.
struct Options {
  std::string world_file;
  macsim::dds::ParticipantOptions participant{0, "", "macsim"};
  double rtf = 1.0;
  double duration = 0.0;
  bool as_fast_as_possible = false;
  bool realtime = false;
  bool validate = false;
  bool strict = false;
  bool keep_overlaps = false;
  bool paused = false;
  bool lockstep = false;
  double status_period = 0.0;
  std::vector<std::string> snapshots;
  double settle = 1.0;
  macsim::render::CameraIntrinsics snapshot_size{640, 480};
  std::string pictures;
  int seed = -1;
  std::string cameras = "320x240";
  double camera_rate = 15.0;
  bool robot_frames = false;
  bool cmd_vel_stamped = false;
  bool viewer = false;
  std::string camera_mode = "MouseKeyboard";
  std::string viewer_screenshot;
  int max_objects = int(macsim::bounds::kMaxObjects);
  int max_import_depth = int(macsim::bounds::kMaxImportDepth);
  int max_imported_files = int(macsim::bounds::kMaxImportedFiles);
  int max_snapshots = int(macsim::SnapshotLimits{}.max_count);
  std::string max_snapshot_bytes = std::to_string(macsim::SnapshotLimits{}.max_bytes);
  int max_pictures = int(macsim::PictureServer::kDefaultMaxFiles);
  int max_queued_commands = int(macsim::kDefaultMaxQueuedCommands);
  macsim::SnapshotLimits snapshot_limits;  // from the two above, once parsed
  std::vector<std::string> data_paths;
  std::string record_session;
  int session_hash_every = 100;
  std::string replay;
  std::optional<macsim::Session> session;  // read from --replay

  macsim::LoadLimits limits() const {
    return {std::size_t(max_import_depth), std::size_t(max_imported_files),
            std::size_t(max_objects)};
  }
};

/// Reads the command line; an exit code if the program should exit now (--help, a bad option).
std::optional<int> parse_options(int argc, char** argv, Options& o) {
  macsim::dds::CommandLine cli("macsim",
                               "Loads a MACSim world, steps its physics and serves it over DDS.");
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
  cli.option("record-session", "FILE",
             "write every command that reaches the world (with its step) and the state hash "
             "every --session-hash-every steps to FILE; --replay runs it again",
             &o.record_session);
  cli.option("session-hash-every", "N",
             "steps between two hashes of a recorded session (default 100)", &o.session_hash_every);
  cli.option("replay", "FILE",
             "replay a recorded session without DDS: its world, its commands at their steps; "
             "checks every hash and exits 0 when all are equal, 1 at the first step that differs",
             &o.replay);
  if (auto code = cli.parse(argc, argv)) return code;
  if (o.session_hash_every < 1) {
    macsim::log::error("macsim: --session-hash-every must be at least 1");
    return 2;
  }
  if (!o.replay.empty()) {
    try {
      o.session = macsim::read_session(o.replay);
    } catch (const macsim::SessionFileError& e) {
      macsim::log::error("macsim: --replay: {}", e.what());
      return 2;
    }
    const auto& header = o.session->header;
    if (!o.world_file.empty() && o.world_file != header.world_file) {
      macsim::log::warn("macsim: replaying on --world {}, not the session's {}", o.world_file,
                        header.world_file);
    }
    if (o.seed != -1 && o.seed != header.seed) {
      macsim::log::warn("macsim: replaying with --seed {}, not the session's {}", o.seed,
                        header.seed);
    }
    if (o.world_file.empty()) o.world_file = header.world_file;
    if (o.seed == -1) o.seed = static_cast<int>(header.seed);
    // Objects started inside each other are parted or kept as they were when it was recorded.
    if (!header.overlaps_parted) {
      o.keep_overlaps = true;
    } else if (o.keep_overlaps || o.strict) {
      macsim::log::warn(
          "macsim: replaying with {}, but the session parted objects that started "
          "inside each other",
          o.strict ? "--strict" : "--keep-overlaps");
    }
  }
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
  if (o.max_objects < 1 || o.max_import_depth < 1 || o.max_imported_files < 1 ||
      o.max_queued_commands < 1) {
    macsim::log::error(
        "macsim: --max-objects, --max-import-depth, --max-imported-files and "
        "--max-queued-commands must be at least 1");
    return 2;
  }
  if (o.world_file.empty()) {
    macsim::log::error("macsim: --world FILE is required (see --help)");
    return 2;
  }
  if (const auto installed = macsim::dds::data_file("worlds/" + o.world_file);
      !std::filesystem::exists(o.world_file) && std::filesystem::path(o.world_file).is_relative() &&
      std::filesystem::exists(installed)) {
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

/// The folders requests may name files in: the world's, the shipped worlds, each --data-path.
std::shared_ptr<const macsim::DataRoots> data_roots(const Options& o) {
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

/// Serves the runner's world over DDS until SIGINT/SIGTERM or --duration; the exit code.
int serve(macsim::Runner& runner, const Options& o, const macsim::SessionWriter* session) {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  macsim::render::ViewerOptions viewer_options;
  if (o.viewer) {
    auto mode = macsim::render::camera_mode_from_name(o.camera_mode);
    if (!mode) {
      macsim::log::error("macsim: unknown --camera-mode '{}'", o.camera_mode);
      return 2;
    }
    viewer_options.mode = *mode;
    viewer_options.screenshot = o.viewer_screenshot;
  }

  // What killed participants (an earlier macsim among them) left in shared memory goes first.
  if (const auto stale = macsim::dds::clean_stale_shared_memory(); !stale.removed.empty()) {
    macsim::log::info("macsim: removed {} stale Fast DDS shared-memory files of killed participants",
                      stale.removed.size());
  }
  try {
    macsim::dds::Participant dds(o.participant);
    macsim::BridgeOptions bridge_options;
    bridge_options.cameras = o.cameras != "off";
    bridge_options.camera_rate = o.camera_rate;
    bridge_options.robot_frames = o.robot_frames;
    bridge_options.cmd_vel_stamped = o.cmd_vel_stamped;
    if (bridge_options.cameras &&
        (!macsim::dds::parse_image_size(o.cameras, &bridge_options.camera.width,
                                        &bridge_options.camera.height) ||
         !(o.camera_rate > 0))) {
      macsim::log::error(
          "macsim: --cameras takes WxH (e.g. 320x240) or off, --camera-rate a positive rate; "
          "got '{}'",
          o.cameras);
      return 2;
    }
    macsim::SimBridge bridge(dds, runner, bridge_options);
    macsim::SupervisorServer supervisor(dds, runner);
    macsim::SimulationServer control(dds, runner, o.limits(), [&bridge](const std::string& robot) {
      return bridge.latest_readings(robot);
    });
    macsim::SimInterfacesServer ros_services(dds, runner, o.limits(), [] { g_stop.store(true); });
    if (!o.pictures.empty()) {
      std::error_code error;
      std::filesystem::create_directories(o.pictures, error);
      if (error) {
        macsim::log::error("macsim: --pictures needs a folder it can create ('{}'): {}",
                           o.pictures, error.message());
        return 2;
      }
    }
    macsim::PictureServer pictures(dds, runner, o.pictures, o.snapshot_size,
                                   std::size_t(o.max_pictures));
    std::vector<std::string> served = bridge.topic_names();
    for (const auto& topic : macsim::SupervisorServer::topic_names()) served.push_back(topic);
    namespace topics = macsim::dds::topics;
    served.push_back(topics::kSimulationRequest + " (macsim_msgs/SimulationRequest, in)");
    served.push_back(topics::kSimulationReply + " (macsim_msgs/SimulationReply, out)");
    served.push_back(topics::kPictureRequest + " (macsim_msgs/PictureRequest, in)");
    served.push_back(topics::kPictureReply + " (macsim_msgs/PictureReply, out)" +
                     (o.pictures.empty() ? ": pictures off" : ""));
    for (const auto& service : macsim::SimInterfacesServer::service_names())
      served.push_back(service);
    macsim::log::info("macsim: serving on DDS domain {}:\n  {}", o.participant.domain,
                      fmt::join(served, "\n  "));
    std::vector<std::string> folders;
    for (const auto& folder : runner.data_roots().folders()) folders.push_back(folder.string());
    macsim::log::info("macsim: requests may name files under: {}", fmt::join(folders, " "));
    for (const auto& folder : runner.data_roots().folders()) {
      // Anyone who may write there may link anything of this user's into it for a request.
      std::error_code error;
      const auto permissions = std::filesystem::status(folder, error).permissions();
      if (!error &&
          (permissions & std::filesystem::perms::others_write) != std::filesystem::perms::none) {
        macsim::log::warn(
            "macsim: warning: the data root {} is writable by every user of this host, who can "
            "place links there for requests to read through; keep worlds in a folder of your own",
            folder.string());
      }
    }
    const std::string pace =
        o.lockstep ? "on request only (lock-step: SIM_STEP requests)"
        : o.paused ? "paused until a SIM_RUN request"
        : o.as_fast_as_possible ? "as fast as possible"
                                : fmt::format("at real-time factor {:g}", o.rtf);
    macsim::log::info("macsim: stepping {}{}", pace,
                      o.duration > 0 ? fmt::format(", for {:g} s of sim time", o.duration) : "");

    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto next_status = start;
    const uint64_t last_step =
        o.duration > 0
            ? static_cast<uint64_t>(std::llround(o.duration / runner.world().step_size()))
            : UINT64_MAX;
    // The viewer (if any) gets a copy of the scene about 30 times a second of wall time.
    std::mutex scene_mutex;
    macsim::Scene latest_scene = macsim::capture_scene(runner.world());
    auto next_scene = start;
    std::atomic<bool> finished{false};
    macsim::StepHooks hooks;
    hooks.before_step = [&] { bridge.poll_commands(); };
    hooks.after_step = [&](macsim::World& world) {
      bridge.publish();
      // Steps on request (lock-step): the step is done when its data is out, images included.
      if (runner.stepping_on_request()) bridge.wait_for_cameras();
      supervisor.publish();
      if (o.viewer && Clock::now() >= next_scene) {
        std::lock_guard<std::mutex> lock(scene_mutex);
        latest_scene = macsim::capture_scene(world);
        next_scene = Clock::now() + std::chrono::milliseconds(33);
      }
      if (o.status_period > 0 && Clock::now() >= next_status) {
        print_status(world);
        next_status += std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(o.status_period));
      }
    };
    // What a step request wanting its data at its end held back: out before its reply (also of
    // a request a pause, a reset or another world cancelled).
    hooks.request_end = [&](macsim::World&) {
      bridge.flush();
      supervisor.flush();
    };
    auto loop = [&] {
      runner.run(g_stop, last_step, hooks);
      finished.store(true);
    };
    if (o.viewer) {
      std::thread physics(loop);
      const int code = macsim::render::run_viewer(
          viewer_options,
          [&] {
            std::lock_guard<std::mutex> lock(scene_mutex);
            return latest_scene;
          },
          [&] { return g_stop.load() || finished.load(); });
      g_stop.store(true);
      physics.join();
      if (code != 0) return code;
    } else {
      loop();
    }
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    const auto& world = runner.world();
    macsim::log::info(
        "macsim: stopped at sim time {:.3f} s after {} steps in {:.3f} s wall: {:.0f} steps/s, "
        "real-time factor {:.2f}",
        world.time(), world.steps(), wall, world.steps() / wall, world.time() / wall);
    // A frame still being rendered is counted once it is done, not whenever the summary comes.
    bridge.wait_for_cameras();
    for (const std::string& summary : {bridge.camera_summary(), bridge.command_summary()}) {
      if (!summary.empty()) macsim::log::info("{}", summary.substr(0, summary.find_last_not_of('\n') + 1));
    }
    std::string counts;
    for (auto source : {macsim::CommandSource::Supervisor, macsim::CommandSource::Simulation,
                        macsim::CommandSource::Ros2Service, macsim::CommandSource::Pictures,
                        macsim::CommandSource::Robot}) {
      counts += fmt::format(" {} {}", macsim::to_string(source), runner.commands_run(source));
    }
    macsim::log::info("macsim: commands run:{}", counts);
    if (!o.record_session.empty()) {
      runner.record(nullptr);  // its closing line
      if (session && !session->ok()) {
        macsim::log::error("macsim: the session {} is incomplete: a write failed (above)",
                           o.record_session);
        return 1;
      }
      macsim::log::info("macsim: session recorded to {}", o.record_session);
    }
  } catch (const macsim::dds::DdsError& e) {
    macsim::log::error("macsim: DDS error: {}", e.what());
    return 3;
  }
  return 0;
}

/// Replays a recorded session on `runner` (its world): no DDS, the commands at their steps.
int replay(macsim::Runner& runner, const Options& o) {
  runner.set_executor(macsim::CommandSource::Supervisor,
                      [&runner](const macsim::Command& c, macsim::World& world) {
                        return macsim::replay(c, world, runner.snapshots());
                      });
  runner.set_executor(macsim::CommandSource::Ros2Service, macsim::sim_interfaces::replay);
  const auto load = [&runner, limits = o.limits()](const macsim::Command& c) {
    const auto source = macsim::load_source(c);
    return source ? macsim::world_parser(runner, limits, *source)
                  : std::function<macsim::WorldSpec()>();
  };
  const auto outcome = macsim::replay_session(*o.session, runner, load);
  std::printf("macsim: %s\n", outcome.message.c_str());
  return outcome.equal ? 0 : 1;
}

}  // namespace

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
  std::unique_ptr<macsim::Runner> runner;
  try {
    macsim::LoadOptions load;
    load.limits = o.limits();
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
  if (o.session) return replay(*runner, o);
  std::shared_ptr<macsim::SessionWriter> session;
  if (!o.record_session.empty()) {
    try {
      session = std::make_shared<macsim::SessionWriter>(
          o.record_session,
          macsim::SessionHeader{o.world_file, o.seed, uint64_t(o.session_hash_every),
                                runner->settings().part_overlaps});
      runner->record(session);
    } catch (const macsim::SessionFileError& e) {
      macsim::log::error("macsim: --record-session: {}", e.what());
      return 2;
    }
  }

  return serve(*runner, o, session.get());
}
