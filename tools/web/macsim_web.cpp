// macsim_web: a live 3D view of a running simulation in a browser. A DDS participant like any
// controller (idl + the client library): it reads the world state, the robot's ground truth,
// crane state, laser and cameras, and serves a three.js page and a WebSocket on
// http://127.0.0.1:PORT/. It never writes a topic.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <thread>

#include "macsim/client/latest.h"
#include "macsim/client/robot_devices.h"
#include "macsim/client/world_state.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/data_files.h"
#include "macsim/dds/log.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/plan_msgsPubSubTypes.h"
#include "web_messages.h"
#include "web_server.h"

namespace {

std::atomic<bool> stop_requested{false};
void on_signal(int) { stop_requested = true; }

using Clock = std::chrono::steady_clock;
namespace sm = sensor_msgs::msg::dds_;

/// Sim seconds per wall second over the last second or so.
class RateOfTime {
 public:
  double update(double sim_time) {
    const auto now = Clock::now();
    if (!start_ || sim_time < start_sim_) {
      start_ = now;
      start_sim_ = sim_time;
      return rtf_;
    }
    const double wall = std::chrono::duration<double>(now - *start_).count();
    if (wall >= 1.0) {
      rtf_ = (sim_time - start_sim_) / wall;
      start_ = now;
      start_sim_ = sim_time;
    }
    return rtf_;
  }

 private:
  std::optional<Clock::time_point> start_;
  double start_sim_ = 0, rtf_ = 0;
};

/// What the page shows, read from DDS. Best effort (Sensor) where the writer is reliable: a
/// viewer needs the newest sample, not every one, and a best-effort reader costs the simulator
/// no acknowledgements. Sim time comes from the stamps (not /clock, written every step).
struct Readers {
  Readers(macsim::dds::Participant& dds, const std::string& robot)
      : world(dds),
        truth(dds, macsim::dds::topics::ground_truth(robot), macsim::dds::QosFamily::Sensor),
        crane(dds, macsim::dds::topics::crane_state(robot), macsim::dds::QosFamily::Sensor),
        odom(dds, macsim::dds::topics::odom(robot), macsim::dds::QosFamily::Sensor),
        plan(dds, macsim::dds::topics::plan(robot), macsim::dds::QosFamily::Latched),
        scan360(dds, macsim::dds::topics::scan(robot, true)),
        scan(dds, macsim::dds::topics::scan(robot, false)),
        points(dds, macsim::dds::topics::points(robot)),
        cameras(dds, robot) {}
  macsim::client::WorldStateClient world;
  macsim::client::Latest<nav_msgs::msg::dds_::Odometry_PubSubType> truth;
  macsim::client::Latest<kurt_msgs::msg::dds_::CraneState_PubSubType> crane;
  macsim::client::Latest<nav_msgs::msg::dds_::Odometry_PubSubType> odom;
  macsim::client::Latest<plan_msgs::msg::dds_::Plan_PubSubType>
      plan;  ///< a controller's, if one publishes
  macsim::client::Latest<sm::LaserScan_PubSubType> scan360, scan;
  macsim::client::Latest<sm::PointCloud2_PubSubType> points;
  macsim::client::StereoCamera cameras;
};

}  // namespace

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{0, "", "macsim_web"};
  macsim::web::WebServer::Options server;
  std::string robot = "kurt";
  double rate = 30.0, image_rate = 5.0;
  int quality = 70, max_points = 4000;
  server.root = macsim::dds::data_file("web");

  macsim::dds::CommandLine cli(
      "macsim_web",
      "Serves a live 3D view of a running simulation (three.js, WebSocket) on\n"
      "http://BIND:PORT/: the world, the doors, the robot and its crane, the laser's scan and\n"
      "cloud, the stereo images, sim time and real-time factor. It only reads topics.");
  cli.participant_options(&participant);
  cli.option("port", "PORT", "TCP port (default 8080; 0: any free one, printed)", &server.port);
  cli.option("bind", "ADDRESS", "address to listen on (default 127.0.0.1: this machine only)",
             &server.bind);
  cli.option("rate", "HZ", "updates per second to each browser (default 30)", &rate);
  cli.option("image-rate", "HZ", "camera images per second to each browser (default 5; 0: none)",
             &image_rate);
  cli.option("robot", "NAME", "the robot to show (default kurt)", &robot);
  cli.option("root", "DIR",
             "the page's files (default: share/macsim/web beside this program's bin/)",
             &server.root);
  int max_clients = int(server.max_clients);
  cli.option("max-clients", "N",
             "browsers connected at once at most; more get HTTP 503 (default " +
                 std::to_string(max_clients) + ")",
             &max_clients);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (!(rate > 0 && rate <= 240) || !(image_rate >= 0 && image_rate <= 60) || server.port < 0 ||
      server.port > 65535 || max_clients < 1) {
    macsim::log::error(
        "macsim_web: --rate is 0..240 Hz, --image-rate 0..60 Hz, --port 0..65535, "
        "--max-clients at least 1");
    return 2;
  }
  server.max_clients = std::size_t(max_clients);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  try {
    macsim::dds::Participant dds(participant);
    // The readers exist only while a browser is connected: an idle macsim_web reads nothing
    // and costs the simulator nothing.
    std::optional<Readers> readers;

    std::mutex scene_mutex;
    std::string scene, update, plan;  // the last ones sent: what a new browser gets first
    macsim::web::WebServer web(
        server,
        [&] {
          std::lock_guard<std::mutex> lock(scene_mutex);
          std::vector<std::string> first;
          if (!scene.empty()) first.push_back(scene);
          if (!update.empty()) first.push_back(update);
          if (!plan.empty()) first.push_back(plan);
          return first;
        },
        [&](const std::string& text) {
          return macsim::web::answer(text, participant.domain, robot);
        });
    std::printf("macsim_web: serving http://%s:%d/ (DDS domain %d, robot '%s')\n",
                server.bind.c_str(), web.port(), participant.domain, robot.c_str());
    std::fflush(stdout);

    RateOfTime rtf;
    std::set<uint32_t> shown;  // the objects of the scene last sent
    double scan_stamp = -1, cloud_stamp = -1, image_stamp = -1;
    auto next = Clock::now(), next_image = Clock::now();
    const auto period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate));
    while (!stop_requested) {
      next += period;
      std::this_thread::sleep_until(next);
      if (Clock::now() > next + period) next = Clock::now();  // late: drop, never catch up
      if (web.clients() == 0) {
        if (readers) {
          readers.reset();
          std::lock_guard<std::mutex> lock(scene_mutex);
          scene.clear();
          update.clear();
          plan.clear();
          shown.clear();
        }
        continue;
      }
      if (!readers) readers.emplace(dds, robot);
      auto& [world, truth, crane, odom, plan_reader, scan360, scan, points, cameras] = *readers;
      const auto objects = world.objects();
      std::set<uint32_t> ids;
      for (const auto& [id, state] : objects) ids.insert(id);
      double sim_time = 0.0;
      for (const auto& [id, state] : objects) sim_time = std::max(sim_time, state.stamp());
      macsim::web::RobotView view;
      if (auto pose = truth.get_shared()) {
        sim_time = std::max(sim_time, macsim::client::stamp_seconds(pose->header()));
        const auto& p = pose->pose().pose();
        view.known = true;
        view.pose = {p.position().x(),    p.position().y(),    p.position().z(),
                     p.orientation().x(), p.orientation().y(), p.orientation().z(),
                     p.orientation().w()};
      }
      if (auto state = crane.get_shared()) {
        view.slew = state->slew();
        view.lift = state->lift();
        view.hoist = state->hoist();
        view.magnet = state->magnet_on();
        view.held = state->held_object();
      }
      {
        std::lock_guard<std::mutex> lock(scene_mutex);
        if (ids != shown || scene.empty()) {
          scene = macsim::web::scene_message(objects, participant.domain, robot);
          shown = ids;
          web.broadcast_state(scene);
        }
        update = macsim::web::update_message(objects, sim_time, rtf.update(sim_time), view);
      }
      web.broadcast_text(update);
      // The plan, when a controller publishes one; its things in the world by where the
      // odometry frame lies (ground truth and odometry of about the same instant).
      if (auto published = plan_reader.get_shared()) {
        std::array<double, 3> frame{0, 0, 0};
        const auto pose = truth.get_shared();
        const auto odometry = odom.get_shared();
        if (pose && odometry)
          frame = macsim::web::odom_in_world(pose->pose().pose(), odometry->pose().pose());
        std::string text = macsim::web::plan_message(*published, frame);
        std::lock_guard<std::mutex> lock(scene_mutex);
        if (text != plan) {
          plan = std::move(text);
          web.broadcast_state(plan);
        }
      }
      for (const auto* source : {&scan360, &scan}) {
        if (auto s = source->get_shared();
            s && macsim::client::stamp_seconds(s->header()) != scan_stamp) {
          scan_stamp = macsim::client::stamp_seconds(s->header());
          web.broadcast_text(macsim::web::scan_message(*s));
        }
      }
      if (auto cloud = points.get_shared();
          cloud && macsim::client::stamp_seconds(cloud->header()) != cloud_stamp) {
        cloud_stamp = macsim::client::stamp_seconds(cloud->header());
        web.broadcast_text(
            macsim::web::cloud_message(macsim::client::to_cloud(*cloud), max_points));
      }
      if (image_rate > 0 && Clock::now() >= next_image) {
        if (auto pair = cameras.latest(image_stamp)) {
          image_stamp = pair->stamp;
          next_image = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(1.0 / image_rate));
          web.broadcast_binary(macsim::web::image_frame('L', pair->left, quality));
          web.broadcast_binary(macsim::web::image_frame('R', pair->right, quality));
        }
      }
    }
    std::printf("macsim_web: stopped (%zu frames skipped for busy browsers)\n",
                web.frames_skipped());
  } catch (const std::exception& e) {
    macsim::log::error("macsim_web: {}", e.what());
    return 1;
  }
  return 0;
}
