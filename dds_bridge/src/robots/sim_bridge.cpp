#include "robots/sim_bridge.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <mutex>

#include "macsim/dds/convert.h"
#include "macsim/dds/kurt_messages.h"
#include "macsim/dds/log.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/rosgraph_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"
#include "macsim/render/camera_rig.h"
#include "macsim/robot/robot_node.h"
#include "robots/simulated_robot.h"

namespace macsim {

namespace sm = sensor_msgs::msg::dds_;
using dds::QosFamily;

struct SimBridge::Clock {
  dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType> writer;
};

/// Robot commands that came while a resumed simulator replayed its session: they wait for its
/// end (run in the replay they would change the world the session rebuilds).
struct SimBridge::Gate {
  std::mutex mutex;
  bool open = true;
  std::vector<Command> parked;  // in arrival order
};

struct SimBridge::RobotTopics {
  RobotTopics(dds::Participant& p, Runner& runner, const std::string& robot_name,
              const robot::NodeOptions& node_options, double camera_rate, Gate& gate)
      : name(robot_name),
        simulated(runner, robot_name),
        // Commands run on the simulation thread, between steps, on the current world's robot.
        node(
            p, simulated,
            [&runner, &gate, this](robot::RobotCommand command, const dds::SampleId& sent) {
              // A value the runner runs on the world's robot (and a session records), unless
              // its sender asked for a reset after sending it (Command::sent_before).
              Command c = robot_command(name, std::move(command));
              c.sent_by = Sender{sent.writer, sent.sequence};
              std::lock_guard<std::mutex> lock(gate.mutex);
              if (!gate.open) {
                gate.parked.push_back(std::move(c));
                return;
              }
              if (runner.push(std::move(c))) return;
              if (commands_dropped.fetch_add(1) == 0) {  // said once; counted in the summary
                log::warn("macsim: {}'s commands are being dropped: {}", name,
                          runner.queue_full_message());
              }
            },
            with_dropped(node_options, runner)),
        camera_instants(camera_rate) {}

  /// The node's options, a sample it drops (not finite) told to the runner as arrived.
  static robot::NodeOptions with_dropped(robot::NodeOptions options, Runner& runner) {
    options.dropped = [&runner](const dds::SampleId& sent) {
      runner.note_arrival(Sender{sent.writer, sent.sequence});
    };
    return options;
  }

  std::string name;
  std::atomic<uint64_t> commands_dropped{0};  // the runner's queue was full (before node)
  SimulatedRobot simulated;
  robot::RobotNode node;
  uint64_t stereo_skipped = 0;  // camera instants skipped while a renderer was still busy
  uint64_t stereo_waited = 0;   // camera instants the simulation waited for a busy renderer
  double seconds_waited = 0.0;  // wall time of those waits
  Schedule camera_instants;
  std::unique_ptr<dds::Writer<sm::Image_PubSubType>> left_image, right_image;
  std::unique_ptr<dds::Writer<sm::CameraInfo_PubSubType>> left_info, right_info;
  // Each eye's last image message, filled again in place by that eye's render thread: a
  // 640x480 frame's 900 KB are then neither allocated nor faulted in again at every frame.
  sm::Image_ left_message, right_message;
  std::vector<std::unique_ptr<render::CameraRig>> cameras;  // one per eye, rendering in parallel
};

namespace {

/// Fills `msg` with a BGR image, reusing the storage its data already has.
const sm::Image_& fill_image(sm::Image_& msg, const cv::Mat& bgr, double stamp,
                             const std::string& frame) {
  msg.header(dds::header(stamp, frame));
  msg.height(bgr.rows);
  msg.width(bgr.cols);
  msg.encoding("bgr8");
  msg.step(bgr.cols * 3);
  msg.data().assign(bgr.data, bgr.data + bgr.total() * 3);
  return msg;
}

/// Pinhole calibration; the right camera's projection carries the baseline.
sm::CameraInfo_ camera_info(const render::CameraIntrinsics& in, double stamp,
                            const std::string& frame, double baseline) {
  sm::CameraInfo_ msg;
  msg.header(dds::header(stamp, frame));
  msg.height(in.height);
  msg.width(in.width);
  msg.distortion_model("plumb_bob");
  msg.d({0, 0, 0, 0, 0});
  const double f = in.focal(), cx = in.width / 2.0, cy = in.height / 2.0;
  msg.k({f, 0, cx, 0, f, cy, 0, 0, 1});
  msg.r({1, 0, 0, 0, 1, 0, 0, 0, 1});
  msg.p({f, 0, cx, -f * baseline, 0, f, cy, 0, 0, 0, 1, 0});
  return msg;
}

}  // namespace

SimBridge::SimBridge(dds::Participant& participant, Runner& runner, const BridgeOptions& options)
    : runner_(runner),
      options_(options),
      clock_(new Clock{{participant, dds::topics::kClock, QosFamily::State}}),
      gate_(std::make_unique<Gate>()) {
  gate_->open = !options_.replaying;
  const QosFamily sensors = dds::sensor_family(options_.lockstep);
  for (const auto& robot : runner.world().robots()) {
    const std::string name = robot->name();
    const std::string frames = options_.robot_frames ? name + "/" : "";
    robot::NodeOptions node;
    node.frame_prefix = frames;
    node.cmd_vel_stamped = options_.cmd_vel_stamped;
    node.sensors = sensors;
    auto topics = std::make_unique<RobotTopics>(participant, runner, name, node,
                                                options_.camera_rate, *gate_);
    const auto stereo = robot->cameras();  // a robot type without cameras has none
    if (options_.cameras && stereo) {
      auto* t = topics.get();
      t->left_image = std::make_unique<dds::Writer<sm::Image_PubSubType>>(
          participant, dds::topics::image(name, "left"), sensors);
      t->right_image = std::make_unique<dds::Writer<sm::Image_PubSubType>>(
          participant, dds::topics::image(name, "right"), sensors);
      t->left_info = std::make_unique<dds::Writer<sm::CameraInfo_PubSubType>>(
          participant, dds::topics::camera_info(name, "left"), sensors);
      t->right_info = std::make_unique<dds::Writer<sm::CameraInfo_PubSubType>>(
          participant, dds::topics::camera_info(name, "right"), sensors);
      const render::CameraIntrinsics in = options_.camera;
      const double baseline = stereo->baseline();
      // Runs on the render thread: writers are thread-safe, the world is never touched.
      auto publish = [t, in, baseline, frames](const render::CameraImage& f) {
        // Each image goes out as soon as it is rendered, with its camera info.
        if (f.eye == render::Eye::Left) {
          const std::string frame = frames + "left_camera_optical_frame";
          t->left_image->write(fill_image(t->left_message, f.image, f.stamp, frame));
          t->left_info->write(camera_info(in, f.stamp, frame, 0.0));
        } else {
          const std::string frame = frames + "right_camera_optical_frame";
          t->right_image->write(fill_image(t->right_message, f.image, f.stamp, frame));
          t->right_info->write(camera_info(in, f.stamp, frame, baseline));
        }
      };
      for (const render::Eye eye : {render::Eye::Left, render::Eye::Right}) {
        t->cameras.push_back(
            std::make_unique<render::CameraRig>(name, in, publish, std::vector<render::Eye>{eye}));
      }
    }
    robots_.push_back(std::move(topics));
  }
  // One way in for a robot command, as for the real robot: the robot interface the node serves
  // (a robot of a world loaded later, not served, is the world's own).
  runner.set_robot_executor([this](const Command& c, World& world) {
    for (auto& t : robots_) {
      if (t->name == c.target) return c.robot && t->simulated.execute(*c.robot);
    }
    return run_robot_command(c, world);
  });
}

SimBridge::~SimBridge() {
  runner_.set_robot_executor({});  // to the world's robots again
}

void SimBridge::poll_commands() {
  for (auto& t : robots_) t->node.poll_commands();
}

void SimBridge::publish() { publish_step(false); }

void SimBridge::replayed_step(bool held) {
  if (!held) {
    replayed_unread_ = true;
    return;
  }
  publish_step(true);
}

void SimBridge::caught_up() {
  replayed_as_sent();
  // The robot commands that came meanwhile, in the order they came, then the gate open.
  std::lock_guard<std::mutex> lock(gate_->mutex);
  for (Command& c : gate_->parked) {
    if (!runner_.push(std::move(c))) {
      log::warn("macsim: a robot command that came while the session replayed was dropped: {}",
                runner_.queue_full_message());
    }
  }
  gate_->parked.clear();
  gate_->open = true;
}

void SimBridge::replayed_as_sent() {
  if (!replayed_unread_) return;
  replayed_unread_ = false;
  // The killed process published these readings, each stamped when it went out (again now,
  // they would go out as new ones stamped now); they are the newest a step request's conditions
  // look at. Replayed to a step that set the world's time: the first read takes everything, as
  // the killed process's would have.
  const World& world = runner_.world();
  if (world.steps() <= world.time_origin().step) return;
  for (auto& t : robots_) t->node.prime();
}

void SimBridge::publish_step(bool replayed) {
  World& world = runner_.world();
  const double now = world.time();
  const World::TimeOrigin origin = world.time_origin();
  if (!started_ || runner_.generation() != generation_ || origin.count != time_origins_) {
    // The first step, a reset, a snapshot restored or a new world: the schedules start at the
    // first step after the time's origin, whatever set it. The instants due before this step
    // were published already, by the process a resumed run took over from.
    started_ = true;
    generation_ = runner_.generation();
    time_origins_ = origin.count;
    const double step = world.step_size();
    const double epoch = static_cast<double>(origin.step + 1) * step;
    // (A request cancelled by a reset publishes without a step: nothing since the origin.)
    const uint64_t last_served = std::max(world.steps(), origin.step + 1) - 1;
    const double served = static_cast<double>(last_served) * step;
    clock_instants_.start(epoch, served);
    for (auto& t : robots_) t->camera_instants.start(epoch, served);
  }
  // A controller's request may ask for its data only at its end (it reads nothing before).
  const StepRequest* request = runner_.step_request();
  const bool hold = replayed || (request && request->publish_at_end);
  if (clock_instants_.due(now)) {
    held_clock_.emplace();
    held_clock_->clock(dds::to_time(now));
  }
  if (!hold) flush_clock();
  for (auto& topics : robots_) {
    topics->node.publish(hold);
    // A replayed step's camera instants were rendered and sent by the killed process: their
    // schedule goes on, nothing is rendered.
    publish_cameras(*topics, now, !replayed && (!request || request->cameras));
  }
}

void SimBridge::flush() {
  flushed_.clear();
  if (held_clock_) flushed_.push_back(clock_->writer.topic_name());
  flush_clock();
  for (auto& topics : robots_) topics->node.flush(&flushed_);
}

void SimBridge::flush_clock() {
  if (!held_clock_) return;
  clock_->writer.write(*held_clock_);
  held_clock_.reset();
}

const robot::Readings* SimBridge::latest_readings(const std::string& robot) const {
  for (const auto& t : robots_) {
    if (robot.empty() || t->name == robot) return &t->node.latest();
  }
  return nullptr;
}

void SimBridge::publish_cameras(RobotTopics& t, double now, bool render) {
  // The schedule goes on whether an instant is rendered or not.
  if (!t.cameras.empty() && t.camera_instants.due(now)) {
    if (!render) return;
    // Both eyes render the same scene or neither does: a stereo pair never mixes two instants.
    bool ready = std::all_of(t.cameras.begin(), t.cameras.end(),
                             [](const auto& rig) { return rig->idle(); });
    // Unpaced (as fast as possible, or steps on request) no frame due in sim time is skipped:
    // the simulation waits for the renderers, and its real-time factor says what that costs.
    // Paced in real time, keeping the pace comes first and a busy renderer skips an instant.
    if (!ready && (runner_.settings().real_time_factor == 0.0 || runner_.stepping_on_request())) {
      const auto start = std::chrono::steady_clock::now();
      for (auto& rig : t.cameras) rig->wait_idle();
      t.seconds_waited +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ++t.stereo_waited;
      ready = true;
    }
    if (ready) {
      const Scene scene = capture_scene(runner_.world());
      for (auto& rig : t.cameras) rig->submit(scene);
    } else {
      ++t.stereo_skipped;
    }
  }
}

void SimBridge::wait_for_cameras() {
  for (auto& t : robots_) {
    for (auto& rig : t->cameras) rig->wait_idle();
  }
}

std::string SimBridge::camera_summary() const {
  std::string summary;
  for (const auto& t : robots_) {
    if (t->cameras.empty()) continue;
    summary += "macsim: " + t->name + "'s cameras: " + std::to_string(t->cameras[0]->rendered()) +
               " stereo pairs rendered, " + std::to_string(t->stereo_skipped) +
               " skipped (a renderer was busy), " + std::to_string(t->stereo_waited) +
               " waited for (" + std::to_string(t->seconds_waited) + " s)\n";
  }
  return summary;
}

std::string SimBridge::command_summary() const {
  std::string summary;
  for (const auto& t : robots_) {
    if (const uint64_t dropped = t->commands_dropped.load(); dropped > 0) {
      summary += "macsim: " + t->name + ": " + std::to_string(dropped) +
                 " commands dropped (the command queue was full)\n";
    }
  }
  return summary;
}

std::vector<std::string> SimBridge::topic_names() const {
  std::vector<std::string> names{dds::topics::kClock + " (rosgraph_msgs/Clock, out)"};
  for (const auto& t : robots_) {
    const auto& n = t->name;
    for (const auto& line : t->node.topic_lines()) names.push_back(line);
    if (!t->cameras.empty()) {
      for (const char* side : {"left", "right"}) {
        names.push_back(dds::topics::image(n, side) + " (sensor_msgs/Image, out)");
        names.push_back(dds::topics::camera_info(n, side) + " (sensor_msgs/CameraInfo, out)");
      }
    }
  }
  return names;
}

}  // namespace macsim
