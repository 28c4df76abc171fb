#include "macsim_runs.h"

#include <fmt/ranges.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <thread>

#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"
#include "macsim/dds/shared_memory.h"
#include "macsim/dds/topics.h"
#include "macsim/dds/wire.h"
#include "macsim/images/image_files.h"
#include "macsim/render/camera_modes.h"
#include "macsim/render/renderer.h"
#include "macsim/render/viewer.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/session.h"
#include "macsim/sim_core/world_loader.h"
#include "pictures/picture_server.h"
#include "robots/sim_bridge.h"
#include "sim_interfaces/sim_interfaces_dispatch.h"
#include "sim_interfaces/sim_interfaces_server.h"
#include "recorded_requests.h"
#include "simulation/simulation_dispatch.h"
#include "simulation/simulation_server.h"
#include "supervisor/supervisor_dispatch.h"
#include "supervisor/supervisor_server.h"

namespace macsim::program {

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) { g_stop.store(true); }

void print_status(const macsim::World& world) {
  for (const auto& robot : world.robots()) {
    const macsim::Pose p = robot->base_footprint_pose();
    const Eigen::Vector3d heading = p.orientation * Eigen::Vector3d::UnitX();
    macsim::log::info(
        "macsim: t={:7.2f} s  {} at x={:.3f} y={:.3f} yaw={:.1f} deg, speed {:.2f} m/s",
        world.time(), robot->name(), p.position.x(), p.position.y(),
        std::atan2(heading.y(), heading.x()) * 180.0 / M_PI, robot->linear_velocity().norm());
  }
}

/// What parses the world a recorded load names, as the live run did (replay and resume).
macsim::SessionWorldLoader session_world_loader(const macsim::Runner& runner, const Options& o) {
  return [&runner, limits = o.limits()](const macsim::Command& c) {
    const auto source = macsim::load_source(c);
    return source ? macsim::world_parser(runner, limits, *source)
                  : std::function<macsim::WorldSpec()>();
  };
}

}  // namespace

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
      if (!macsim::images::write_image(file, image)) {
        macsim::log::error("macsim: cannot write '{}'", file);
        return 1;
      }
      macsim::log::info("macsim: wrote {} view to {} ({}x{}, {})", render::camera_mode_name(mode),
                        file, intrinsics.width, intrinsics.height, renderer.gl_renderer());
    }
  } catch (const render::RenderError& e) {
    macsim::log::error("macsim: cannot render offscreen: {}", e.what());
    return 1;
  } catch (const macsim::images::CodecsUnavailable& e) {
    macsim::log::error("macsim: cannot write a snapshot: {}", e.what());
    return 1;
  }
  return 0;
}

namespace {

/// The viewer's options of --camera-mode and --viewer-screenshot, or nothing (said) when the
/// mode is unknown.
std::optional<macsim::render::ViewerOptions> viewer_options_of(const Options& o) {
  macsim::render::ViewerOptions viewer_options;
  if (!o.viewer) return viewer_options;
  auto mode = macsim::render::camera_mode_from_name(o.camera_mode);
  if (!mode) {
    macsim::log::error("macsim: unknown --camera-mode '{}'", o.camera_mode);
    return std::nullopt;
  }
  viewer_options.mode = *mode;
  viewer_options.screenshot = o.viewer_screenshot;
  return viewer_options;
}

/// The bridge's options of the command line, or nothing (said) when --cameras or --camera-rate
/// are not what they take.
std::optional<macsim::BridgeOptions> bridge_options_of(const Options& o, bool replaying) {
  macsim::BridgeOptions bridge_options;
  bridge_options.cameras = o.cameras != "off";
  bridge_options.camera_rate = o.camera_rate;
  bridge_options.robot_frames = o.robot_frames;
  bridge_options.cmd_vel_stamped = o.cmd_vel_stamped;
  bridge_options.lockstep = o.lockstep;
  bridge_options.replaying = replaying;
  // The camera schedule runs with cameras off too (a world's schedule is one).
  if (!(std::isfinite(o.camera_rate) && o.camera_rate > 0) ||
      (bridge_options.cameras &&
       !macsim::dds::parse_image_size(o.cameras, &bridge_options.camera.width,
                                      &bridge_options.camera.height))) {
    macsim::log::error(
        "macsim: --cameras takes WxH (e.g. 320x240) or off, --camera-rate a finite positive "
        "rate (Hz); got --cameras '{}' --camera-rate {}",
        o.cameras, o.camera_rate);
    return std::nullopt;
  }
  return bridge_options;
}

/// True when --pictures names no folder, or one that is there or could be made (else said).
bool pictures_folder_ready(const Options& o) {
  if (o.pictures.empty()) return true;
  std::error_code error;
  std::filesystem::create_directories(o.pictures, error);
  if (!error) return true;
  macsim::log::error("macsim: --pictures needs a folder it can create ('{}'): {}", o.pictures,
                     error.message());
  return false;
}

/// Says what is served on which domain, where requests may read files (and warns of a data
/// root every user may write to), and how the world will step.
void log_serving(const macsim::Runner& runner, const macsim::SimBridge& bridge, const Options& o) {
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
  const std::string pace = o.lockstep ? "on request only (lock-step: SIM_STEP requests)"
                           : o.paused ? "paused until a SIM_RUN request"
                           : o.as_fast_as_possible ? "as fast as possible"
                                                   : fmt::format("at real-time factor {:g}", o.rtf);
  macsim::log::info("macsim: stepping {}{}", pace,
                    o.duration > 0 ? fmt::format(", for {:g} s of sim time", o.duration) : "");
}

/// Says how fast the run went, what the cameras and commands did, and closes the session (if
/// one is recorded); 1 when its file is incomplete.
int log_summary(macsim::Runner& runner, macsim::SimBridge& bridge, const Options& o,
                const macsim::SessionWriter* session, double wall) {
  const auto& world = runner.world();
  macsim::log::info(
      "macsim: stopped at sim time {:.3f} s after {} steps in {:.3f} s wall: {:.0f} steps/s, "
      "real-time factor {:.2f}",
      world.time(), world.steps(), wall, world.steps() / wall, world.time() / wall);
  // A frame still being rendered is counted once it is done, not whenever the summary comes.
  bridge.wait_for_cameras();
  for (const std::string& summary : {bridge.camera_summary(), bridge.command_summary()}) {
    if (!summary.empty())
      macsim::log::info("{}", summary.substr(0, summary.find_last_not_of('\n') + 1));
  }
  std::string counts;
  for (auto source : {macsim::CommandSource::Supervisor, macsim::CommandSource::Simulation,
                      macsim::CommandSource::Ros2Service, macsim::CommandSource::Pictures,
                      macsim::CommandSource::Robot}) {
    counts += fmt::format(" {} {}", macsim::to_string(source), runner.commands_run(source));
  }
  macsim::log::info("macsim: commands run:{}", counts);
  if (const uint64_t late = runner.commands_sent_before_reset(); late > 0) {
    macsim::log::info(
        "macsim: {} robot commands sent before a reset (or restore, or load) arrived after it "
        "and were dropped",
        late);
  }
  if (session) {
    const std::string& path = o.record_session.empty() ? o.resume : o.record_session;
    runner.record(nullptr);  // its closing line
    if (!session->ok()) {
      macsim::log::error("macsim: the session {} is incomplete: a write failed (above)", path);
      return 1;
    }
    macsim::log::info("macsim: session recorded to {}", path);
  }
  return 0;
}

/// Steps the world until stopped or --duration is reached, the bridge and the supervisor
/// served around each step and each request, the viewer (if any) on this thread; the wall time
/// it took in `wall`; the viewer's exit code if it failed.
int step_world(macsim::Runner& runner, const Options& o, macsim::SimBridge& bridge,
               macsim::SupervisorServer& supervisor,
               const macsim::render::ViewerOptions& viewer_options, double& wall) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto next_status = start;
  const uint64_t last_step =
      o.duration > 0 ? static_cast<uint64_t>(std::llround(o.duration / runner.world().step_size()))
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
    // A kill at a chosen step (tests of --resume): as SIGKILL from outside, nothing after it.
    if (o.kill_at_step > 0 && runner.steps_run() == uint64_t(o.kill_at_step)) std::raise(SIGKILL);
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
  wall = std::chrono::duration<double>(Clock::now() - start).count();
  return 0;
}

}  // namespace

int serve(macsim::Runner& runner, const Options& o, const macsim::SessionWriter* session,
          Resumed* resumed) {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const auto viewer_options = viewer_options_of(o);
  if (!viewer_options) return 2;

  // What killed participants (an earlier macsim among them) left in shared memory goes first.
  if (const auto stale = macsim::dds::clean_stale_shared_memory(); !stale.removed.empty()) {
    macsim::log::info(
        "macsim: removed {} stale Fast DDS shared-memory files of killed participants",
        stale.removed.size());
  }
  try {
    macsim::dds::Participant dds(o.participant);
    const auto bridge_options = bridge_options_of(o, resumed && resumed->catch_up);
    if (!bridge_options) return 2;
    macsim::SimBridge bridge(dds, runner, *bridge_options);
    if (resumed && resumed->catch_up) {
      if (const int code = resumed->catch_up(bridge)) return code;
      session = resumed->writer.get();
    }
    macsim::SupervisorServer supervisor(dds, runner);
    macsim::SimulationServer control(
        dds, runner, o.limits(),
        [&bridge](const std::string& robot) { return bridge.latest_readings(robot); },
        macsim::SimulationServer::HeldOutput{[&bridge, &supervisor] {
                                               bridge.flush();
                                               supervisor.flush();
                                             },
                                             [&bridge] { return bridge.flushed(); }});
    macsim::SimInterfacesServer ros_services(dds, runner, o.limits(), [] { g_stop.store(true); });
    if (!pictures_folder_ready(o)) return 2;
    macsim::PictureServer pictures(dds, runner, o.pictures, o.snapshot_size,
                                   std::size_t(o.max_pictures));
    if (resumed) {  // what the killed run answered is answered again, never run again
      supervisor.remember(resumed->supervisor_replies);
      control.resume(resumed->requests);
    }
    log_serving(runner, bridge, o);

    double wall = 0.0;
    if (const int code = step_world(runner, o, bridge, supervisor, *viewer_options, wall))
      return code;
    if (const int code = log_summary(runner, bridge, o, session, wall)) return code;
  } catch (const macsim::dds::DdsError& e) {
    macsim::log::error("macsim: DDS error: {}", e.what());
    return 3;
  }
  return 0;
}

int replay(macsim::Runner& runner, const Options& o) {
  runner.set_executor<macsim::SupervisorCall>(
      [&runner](const macsim::SupervisorCall& q, const macsim::Command&, macsim::World& world) {
        macsim::dispatch(q.message(), world, runner.snapshots());  // as served, unanswered
        return true;
      });
  macsim::sim_interfaces::replay_on(runner);
  const auto load = session_world_loader(runner, o);
  const auto outcome = macsim::replay_session(*o.session, runner, load, o.session_files.get(), {},
                                              macsim::read_recorded_request);
  std::printf("macsim: %s\n", outcome.message.c_str());
  return outcome.equal ? 0 : 1;
}

namespace {

/// Steps of a step request (their step counts after each, first to last).
struct StepSpan {
  uint64_t first = 0, last = 0;
};

/// The steps of the step request a killed process had begun and kept its data back for
/// (STEP_PUBLISH_AT_END), if the session's last step request taken is one never answered.
std::optional<StepSpan> held_steps(const macsim::Session& session) {
  namespace mm = macsim_msgs::msg::dds_;
  const auto begun = macsim::SimulationServer::begun(session.requests);
  if (begun.empty()) return std::nullopt;
  // The session's last request taken: only it can have been stepping at the kill.
  std::optional<mm::SimulationRequest_> last;
  for (const auto& r : session.requests) {
    if (r.service == macsim::SimulationServer::kSessionService &&
        r.kind == macsim::RecordedRequest::Kind::Taken)
      last = macsim::dds::from_wire<mm::SimulationRequest_PubSubType>(r.bytes);
  }
  const auto& b = begun.back();
  if (!last || last->client_id() != b.request.client_id() ||
      last->sequence_number() != b.request.sequence_number() ||
      b.request.command() != mm::SIM_STEP || !(b.request.step_options() & mm::STEP_PUBLISH_AT_END))
    return std::nullopt;
  // Taken after its first step, with the steps it had left.
  return StepSpan{b.first_step, b.step + b.request.steps()};
}

}  // namespace

int resume(macsim::Runner& runner, const Options& o) {
  const macsim::Session& session = *o.session;
  Resumed resumed;
  resumed.requests = session.requests;
  const auto held = held_steps(session);
  resumed.catch_up = [&runner, &o, &session, &resumed, held](macsim::SimBridge& bridge) {
    // The supervisor's requests run as they did, their replies kept for a repeat (the latest
    // ones: a client repeats only what it had in flight).
    constexpr std::size_t kKeptReplies = 4096;
    runner.set_executor<macsim::SupervisorCall>([&runner, &resumed](const macsim::SupervisorCall& q,
                                                                    const macsim::Command&,
                                                                    macsim::World& world) {
      auto& replies = resumed.supervisor_replies;
      if (replies.size() >= 2 * kKeptReplies)
        replies.erase(replies.begin(), replies.begin() + kKeptReplies);
      replies.push_back(macsim::dispatch(q.message(), world, runner.snapshots()));
      return true;
    });
    macsim::sim_interfaces::replay_on(runner);
    const auto load = session_world_loader(runner, o);
    const auto start = std::chrono::steady_clock::now();
    // A step's readings as the killed process took them: kept back in the begun request's
    // steps, else gone out with it (up to the step before the request's first, then).
    const auto outcome = macsim::replay_session(
        session, runner, load, o.session_files.get(),
        [&] {
          const uint64_t step = runner.steps_run();
          bridge.replayed_step(held && step >= held->first && step <= held->last);
          if (held && step + 1 == held->first) bridge.replayed_as_sent();
        },
        macsim::read_recorded_request);
    bridge.caught_up();
    if (!outcome.equal) {
      macsim::log::error("macsim: --resume: cannot resume {}: {}", o.resume, outcome.message);
      return 1;
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    macsim::log::info(
        "macsim: resumed {} at step {} (sim time {:.3f} s) in {:.2f} s: {} commands and {} "
        "hashes as recorded; {}",
        o.resume, runner.steps_run(), runner.world().time(), wall, outcome.commands_run,
        outcome.hashes_checked,
        session.cut_short ? "the session was cut short by a kill: steps the killed run took "
                            "after its last record are run again"
                          : "the session had ended cleanly");
    // From here requests read the disk again (the files they read going into the session).
    Options live = o;
    live.session_files.reset();
    try {
      auto writer = std::make_shared<macsim::SessionWriter>(o.resume, session);
      runner.set_data_roots(
          data_roots(live)->watched([writer](const std::string& path, const std::string& bytes) {
            writer->file(path, bytes);
          }));
      runner.record(writer, /*resumed=*/true);
      resumed.writer = std::move(writer);
    } catch (const std::invalid_argument& e) {
      macsim::log::error("macsim: --data-path: {}", e.what());
      return 2;
    } catch (const macsim::SessionFileError& e) {
      macsim::log::error("macsim: --resume: {}", e.what());
      return 2;
    }
    return 0;
  };
  return serve(runner, o, nullptr, &resumed);
}

}  // namespace macsim::program
