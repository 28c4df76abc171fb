// macsim: loads a world, steps it and serves it over Fast DDS.
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
#include "macsim/dds/shared_memory.h"
#include "macsim/dds/topics.h"
#include "macsim/dds/wire.h"
#include "macsim/render/camera_modes.h"
#include "macsim/render/renderer.h"
#include "macsim/render/viewer.h"
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

void print_summary(const macsim::WorldSpec& spec) {
  std::map<std::string, int> kinds;
  int portable = 0;
  for (const auto& o : spec.objects) {
    portable += o.portable ? 1 : 0;
    static const char* names[] = {"objects",          "walls",       "ramps",      "switch bases",
                                  "switch platforms", "door frames", "door leaves"};
    ++kinds[names[static_cast<int>(o.kind)]];
  }
  std::cout << "world '" << spec.name << "' from " << spec.file << ": " << spec.objects.size()
            << " objects (" << portable << " portable, " << spec.objects.size() - portable
            << " fixed; ";
  bool first = true;
  for (const auto& [kind, count] : kinds) {
    std::cout << (first ? "" : ", ") << count << " " << kind;
    first = false;
  }
  std::cout << "), " << spec.doors.size() << " doors, " << spec.robots.size() << " robots";
  for (const auto& r : spec.robots) std::cout << " [" << r.name << ": " << r.type << "]";
  std::cout << ", step " << spec.physics.step * 1e3 << " ms" << std::endl;
}

void print_status(const macsim::World& world) {
  for (const auto& robot : world.robots()) {
    const macsim::Pose p = robot->base_footprint_pose();
    const Eigen::Vector3d heading = p.orientation * Eigen::Vector3d::UnitX();
    std::printf("macsim: t=%7.2f s  %s at x=%.3f y=%.3f yaw=%.1f deg, speed %.2f m/s\n",
                world.time(), robot->name().c_str(), p.position.x(), p.position.y(),
                std::atan2(heading.y(), heading.x()) * 180.0 / M_PI,
                robot->linear_velocity().norm());
  }
  std::fflush(stdout);
}

/// --snapshot: settle, render each requested camera mode offscreen, write the PNGs.
int write_snapshots(macsim::Runner& runner, const std::vector<std::string>& requests, double settle,
                    const std::string& size) {
  namespace render = macsim::render;
  std::vector<std::pair<render::CameraMode, std::string>> jobs;
  for (const auto& request : requests) {
    const auto colon = request.find(':');
    const auto mode = colon == std::string::npos
                          ? std::nullopt
                          : render::camera_mode_from_name(request.substr(0, colon));
    if (!mode || colon + 1 >= request.size()) {
      std::cerr
          << "macsim: --snapshot takes MODE:FILE.png with MODE one of MouseOnly, "
             "MouseKeyboard, FixedFollow, Follow, Inside, LeftCamera, RightCamera, Manual, Chase; "
             "got '"
          << request << "'\n";
      return 2;
    }
    jobs.emplace_back(*mode, request.substr(colon + 1));
  }
  render::CameraIntrinsics intrinsics;
  if (std::sscanf(size.c_str(), "%dx%d", &intrinsics.width, &intrinsics.height) != 2 ||
      intrinsics.width <= 0 || intrinsics.height <= 0) {
    std::cerr << "macsim: --snapshot-size takes WxH, e.g. 640x480; got '" << size << "'\n";
    return 2;
  }
  if (settle < 0) {
    std::cerr << "macsim: --settle must not be negative\n";
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
        std::cerr << "macsim: cannot write '" << file << "'\n";
        return 1;
      }
      std::cout << "macsim: wrote " << render::camera_mode_name(mode) << " view to " << file << " ("
                << intrinsics.width << "x" << intrinsics.height << ", " << renderer.gl_renderer()
                << ")" << std::endl;
    }
  } catch (const render::RenderError& e) {
    std::cerr << "macsim: cannot render offscreen: " << e.what() << std::endl;
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
  bool paused = false;
  bool lockstep = false;
  double status_period = 0.0;
  std::vector<std::string> snapshots;
  double settle = 1.0;
  std::string snapshot_size = "640x480";
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
  cli.option("snapshot-size", "WxH", "image size of --snapshot and --pictures (default 640x480)",
             &o.snapshot_size);
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
    std::cerr << "macsim: --session-hash-every must be at least 1\n";
    return 2;
  }
  if (!o.replay.empty()) {
    try {
      o.session = macsim::read_session(o.replay);
    } catch (const macsim::SessionFileError& e) {
      std::cerr << "macsim: --replay: " << e.what() << "\n";
      return 2;
    }
    const auto& header = o.session->header;
    if (!o.world_file.empty() && o.world_file != header.world_file) {
      std::cerr << "macsim: replaying on --world " << o.world_file << ", not the session's "
                << header.world_file << "\n";
    }
    if (o.seed != -1 && o.seed != header.seed) {
      std::cerr << "macsim: replaying with --seed " << o.seed << ", not the session's "
                << header.seed << "\n";
    }
    if (o.world_file.empty()) o.world_file = header.world_file;
    if (o.seed == -1) o.seed = static_cast<int>(header.seed);
  }
  {
    unsigned long long bytes = 0;
    const std::string& text = o.max_snapshot_bytes;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), bytes);
    if (error != std::errc() || end != text.data() + text.size() || o.max_snapshots < 1 ||
        o.max_pictures < 1) {
      std::cerr << "macsim: --max-snapshots and --max-pictures must be at least 1, "
                   "--max-snapshot-bytes a count of bytes; got '"
                << text << "'\n";
      return 2;
    }
    o.snapshot_limits = {std::size_t(o.max_snapshots), std::size_t(bytes)};
  }
  if (o.max_objects < 1 || o.max_import_depth < 1 || o.max_imported_files < 1 ||
      o.max_queued_commands < 1) {
    std::cerr << "macsim: --max-objects, --max-import-depth, --max-imported-files and "
                 "--max-queued-commands must be at least 1\n";
    return 2;
  }
  if (o.world_file.empty()) {
    std::cerr << "macsim: --world FILE is required (see --help)\n";
    return 2;
  }
  if (const auto installed = macsim::dds::data_file("worlds/" + o.world_file);
      !std::filesystem::exists(o.world_file) && std::filesystem::path(o.world_file).is_relative() &&
      std::filesystem::exists(installed)) {
    o.world_file = installed;
  }
  if (o.seed < -1) {
    std::cerr << "macsim: --seed must be 0 or more, got " << o.seed << "\n";
    return 2;
  }
  if (!(o.rtf >= macsim::kMinRealTimeFactor) || !std::isfinite(o.rtf) || !(o.duration >= 0.0) ||
      !(o.status_period >= 0.0)) {
    std::cerr << "macsim: --rtf must be at least " << macsim::kMinRealTimeFactor
              << ", --duration and --status not negative\n";
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
int serve(macsim::Runner& runner, const Options& o) {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  macsim::render::ViewerOptions viewer_options;
  if (o.viewer) {
    auto mode = macsim::render::camera_mode_from_name(o.camera_mode);
    if (!mode) {
      std::cerr << "macsim: unknown --camera-mode '" << o.camera_mode << "'\n";
      return 2;
    }
    viewer_options.mode = *mode;
    viewer_options.screenshot = o.viewer_screenshot;
  }

  // What killed participants (an earlier macsim among them) left in shared memory goes first.
  if (const auto stale = macsim::dds::clean_stale_shared_memory(); !stale.removed.empty()) {
    std::cout << "macsim: removed " << stale.removed.size()
              << " stale Fast DDS shared-memory files of killed participants" << std::endl;
  }
  try {
    macsim::dds::Participant dds(o.participant);
    macsim::BridgeOptions bridge_options;
    bridge_options.cameras = o.cameras != "off";
    bridge_options.camera_rate = o.camera_rate;
    bridge_options.robot_frames = o.robot_frames;
    bridge_options.cmd_vel_stamped = o.cmd_vel_stamped;
    if (bridge_options.cameras &&
        (std::sscanf(o.cameras.c_str(), "%dx%d", &bridge_options.camera.width,
                     &bridge_options.camera.height) != 2 ||
         bridge_options.camera.width <= 0 || bridge_options.camera.height <= 0 ||
         o.camera_rate <= 0)) {
      std::cerr << "macsim: --cameras takes WxH (e.g. 320x240) or off, --camera-rate a positive "
                   "rate; got '"
                << o.cameras << "'\n";
      return 2;
    }
    macsim::SimBridge bridge(dds, runner, bridge_options);
    macsim::SupervisorServer supervisor(dds, runner);
    macsim::SimulationServer control(dds, runner, o.limits(), [&bridge](const std::string& robot) {
      return bridge.latest_readings(robot);
    });
    macsim::SimInterfacesServer ros_services(dds, runner, o.limits(), [] { g_stop.store(true); });
    macsim::render::CameraIntrinsics picture_size;
    if (!o.pictures.empty()) {
      std::error_code error;
      std::filesystem::create_directories(o.pictures, error);
      if (error ||
          std::sscanf(o.snapshot_size.c_str(), "%dx%d", &picture_size.width,
                      &picture_size.height) != 2 ||
          picture_size.width <= 0 || picture_size.height <= 0) {
        std::cerr << "macsim: --pictures needs a folder it can create ('" << o.pictures
                  << "') and --snapshot-size WxH ('" << o.snapshot_size << "')\n";
        return 2;
      }
    }
    macsim::PictureServer pictures(dds, runner, o.pictures, picture_size,
                                   std::size_t(o.max_pictures));
    std::cout << "macsim: serving on DDS domain " << o.participant.domain << ":\n";
    for (const auto& topic : bridge.topic_names()) std::cout << "  " << topic << "\n";
    for (const auto& topic : macsim::SupervisorServer::topic_names())
      std::cout << "  " << topic << "\n";
    std::cout << "  " << macsim::dds::topics::kSimulationRequest
              << " (macsim_msgs/SimulationRequest, in)\n  " << macsim::dds::topics::kSimulationReply
              << " (macsim_msgs/SimulationReply, out)\n  " << macsim::dds::topics::kPictureRequest
              << " (macsim_msgs/PictureRequest, in)\n  " << macsim::dds::topics::kPictureReply
              << " (macsim_msgs/PictureReply, out)" << (o.pictures.empty() ? ": pictures off" : "")
              << "\n";
    for (const auto& service : macsim::SimInterfacesServer::service_names())
      std::cout << "  " << service << "\n";
    std::cout << "macsim: requests may name files under:";
    for (const auto& folder : runner.data_roots().folders()) std::cout << " " << folder.string();
    std::cout << "\n";
    for (const auto& folder : runner.data_roots().folders()) {
      // Anyone who may write there may link anything of this user's into it for a request.
      std::error_code error;
      const auto permissions = std::filesystem::status(folder, error).permissions();
      if (!error &&
          (permissions & std::filesystem::perms::others_write) != std::filesystem::perms::none) {
        std::cerr << "macsim: warning: the data root " << folder.string()
                  << " is writable by every user of this host, who can place links there for "
                     "requests to read through; keep worlds in a folder of your own\n";
      }
    }
    if (o.lockstep) {
      std::printf("macsim: stepping on request only (lock-step: SIM_STEP requests)");
    } else if (o.paused) {
      std::printf("macsim: stepping paused until a SIM_RUN request");
    } else if (o.as_fast_as_possible) {
      std::printf("macsim: stepping as fast as possible");
    } else {
      std::printf("macsim: stepping at real-time factor %g", o.rtf);
    }
    if (o.duration > 0) std::printf(", for %g s of sim time", o.duration);
    std::printf("\n");
    std::fflush(stdout);

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
    std::printf(
        "macsim: stopped at sim time %.3f s after %llu steps in %.3f s wall: %.0f steps/s, "
        "real-time factor %.2f\n",
        world.time(), static_cast<unsigned long long>(world.steps()), wall, world.steps() / wall,
        world.time() / wall);
    // A frame still being rendered is counted once it is done, not whenever the summary comes.
    bridge.wait_for_cameras();
    std::printf("%s", bridge.camera_summary().c_str());
    std::printf("%s", bridge.command_summary().c_str());
    std::printf("macsim: commands run:");
    for (auto source : {macsim::CommandSource::Supervisor, macsim::CommandSource::Simulation,
                        macsim::CommandSource::Ros2Service, macsim::CommandSource::Pictures,
                        macsim::CommandSource::Robot}) {
      std::printf(" %s %llu", std::string(macsim::to_string(source)).c_str(),
                  static_cast<unsigned long long>(runner.commands_run(source)));
    }
    std::printf("\n");
    if (!o.record_session.empty()) {
      runner.record(nullptr);  // its closing line
      std::printf("macsim: session recorded to %s\n", o.record_session.c_str());
    }
  } catch (const macsim::dds::DdsError& e) {
    std::cerr << "macsim: DDS error: " << e.what() << std::endl;
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
  std::unique_ptr<macsim::Runner> runner;
  try {
    macsim::LoadOptions load;
    load.warn = [](const std::string& warning) { std::cerr << warning << "\n"; };
    load.limits = o.limits();
    auto spec = macsim::load_world_file(o.world_file, load);
    print_summary(spec);
    if (o.seed >= 0) {
      const auto moved = macsim::vary_world(spec, static_cast<uint32_t>(o.seed));
      std::cout << "macsim: layout of seed " << o.seed << ":\n";
      for (const auto& line : moved) std::cout << "  " << line << "\n";
    }
    macsim::RunSettings settings;
    settings.paused = o.paused || o.lockstep;
    settings.real_time_factor = o.as_fast_as_possible ? 0.0 : o.rtf;
    settings.refuse_overlaps = o.strict;  // for worlds loaded later by a request
    settings.warn = load.warn;
    settings.max_queued_commands = std::size_t(o.max_queued_commands);
    runner = std::make_unique<macsim::Runner>(std::move(spec), settings);
    const auto overlaps = macsim::admit_overlaps(runner->world(), o.strict, load.warn);
    if (o.validate) {
      std::cout << "macsim: "
                << (overlaps.empty() ? "no objects start inside each other"
                                     : macsim::overlap_error(overlaps, 0) + " (warnings above)")
                << std::endl;
    }
  } catch (const macsim::WorldFileError& e) {
    std::cerr << "macsim: " << e.what() << std::endl;
    return 1;
  }
  try {
    runner->set_data_roots(data_roots(o));
  } catch (const std::invalid_argument& e) {
    std::cerr << "macsim: --data-path: " << e.what() << std::endl;
    return 2;
  }
  runner->snapshots().set_limits(o.snapshot_limits);
  runner->set_max_objects(std::size_t(o.max_objects));
  if (o.validate) return 0;
  if (!o.snapshots.empty()) return write_snapshots(*runner, o.snapshots, o.settle, o.snapshot_size);
  if (o.session) return replay(*runner, o);
  if (!o.record_session.empty()) {
    try {
      runner->record(std::make_shared<macsim::SessionWriter>(
          o.record_session,
          macsim::SessionHeader{o.world_file, o.seed, uint64_t(o.session_hash_every)}));
    } catch (const macsim::SessionFileError& e) {
      std::cerr << "macsim: --record-session: " << e.what() << std::endl;
      return 2;
    }
  }

  return serve(*runner, o);
}
