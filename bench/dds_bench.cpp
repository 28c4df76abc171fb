// Round trips over DDS, each beside its baseline in the same run (machines here are noisy):
// a bare Fast DDS ping-pong between two processes with the same payload types, then the same
// exchange through macsim: supervisor request/reply, lock-step Step(1), twist -> odometry, and
// 640x480 stereo images. Prints `name value unit` lines.
//   bench_dds [ROUND_TRIPS]   (from the repository root)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "image_source.h"
#include "macsim/client/supervisor_client.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"
#include "macsim/process/child_process.h"

namespace {

namespace mm = macsim_msgs::msg::dds_;
namespace gm = geometry_msgs::msg::dds_;
namespace nm = nav_msgs::msg::dds_;
namespace sm = sensor_msgs::msg::dds_;
using Clock = std::chrono::steady_clock;
using macsim::dds::QosFamily;

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * v.size()))];
}

void report(const std::string& name, const std::vector<double>& us) {
  std::printf("%s.p50 %.1f us\n%s.p99 %.1f us\n", name.c_str(), percentile(us, 0.5), name.c_str(),
              percentile(us, 0.99));
}

void ratio(const std::string& name, const std::vector<double>& us,
           const std::vector<double>& bare) {
  std::printf("%s_over_bare.p50 %.2f x\n", name.c_str(),
              percentile(us, 0.5) / percentile(bare, 0.5));
}

double micros_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

/// The bare baselines' echo process: a supervisor request comes back as a reply with the same
/// correlation; a twist comes back as an odometry message (the sizes of the real exchanges).
[[noreturn]] void pong(int domain) {
  macsim::dds::Participant p({domain, "", "bench_pong"});
  macsim::dds::Writer<mm::SupervisorReply_PubSubType> replies(p, "bench/pong", QosFamily::Command);
  macsim::dds::Reader<mm::SupervisorRequest_PubSubType> requests(
      p, "bench/ping", QosFamily::Command, [&](const mm::SupervisorRequest_& r) {
        mm::SupervisorReply_ reply;
        reply.client_id(r.client_id());
        reply.sequence_number(r.sequence_number());
        replies.write(reply);
      });
  macsim::dds::Writer<nm::Odometry_PubSubType> odom(p, "bench/odom", QosFamily::Sensor);
  macsim::dds::Reader<gm::Twist_PubSubType> twists(p, "bench/cmd_vel", QosFamily::Command,
                                                   [&](const gm::Twist_& twist) {
                                                     nm::Odometry_ o;
                                                     o.twist().twist(twist);
                                                     odom.write(o);
                                                   });
  while (true) std::this_thread::sleep_for(std::chrono::seconds(1));
}

/// The images' bare baseline (image_source.h) on "bench/image".
[[noreturn]] void image_source(int domain) {
  macsim::dds::Participant p({domain, "", "bench_images"});
  macsim::bench::publish_images(p, "bench/image");
}

/// A server process of the benchmark: its standard output discarded (keeps the figures
/// readable), its errors on ours; stopped (SIGTERM) and reaped when the handle goes.
std::unique_ptr<macsim::process::ChildProcess> spawn(std::vector<std::string> argv) {
  macsim::process::Options options;
  options.output = macsim::process::Output::discard();
  options.merge_stderr = false;
  return std::make_unique<macsim::process::ChildProcess>(std::move(argv), options);
}

/// One request/reply exchange measured against the others: its call and its round trips (us).
struct Exchange {
  std::string name;
  std::function<bool()> call;
  std::vector<double> us;
};

/// `n` round trips of every exchange, in blocks of `n / 20` taken in turn (after 50 warm-up
/// calls each), so all of them see the same machine noise: the ratios compare like with like.
void interleave(std::vector<Exchange>& exchanges, int n) {
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let discovery settle both ways
  for (auto& e : exchanges) {
    for (int i = 0; i < 50; ++i) e.call();
  }
  const int block = std::max(1, n / 20);
  for (int done = 0; done < n; done += block) {
    for (auto& e : exchanges) {
      for (int i = 0; i < std::min(block, n - done); ++i) {
        const auto t0 = Clock::now();
        if (!e.call()) {
          std::fprintf(stderr, "bench_dds: %s: a call got no reply\n", e.name.c_str());
          continue;
        }
        e.us.push_back(micros_since(t0));
      }
    }
  }
}

/// Twist out, the first odometry whose twist shows it back (us per trial). Trials alternate
/// forward and backward at 0.2 m/s; between trials the robot is stopped and left to settle.
std::vector<double> twist_to_odometry(macsim::dds::Participant& p, const std::string& cmd_topic,
                                      const std::string& odom_topic, int trials) {
  std::mutex mutex;
  std::condition_variable seen;
  double direction = 0.0;  // the trial's commanded direction; 0: no trial running
  std::optional<Clock::time_point> sent;
  std::vector<double> us;
  bool matched_odom = false;
  macsim::dds::Writer<gm::Twist_PubSubType> cmd(p, cmd_topic, QosFamily::Command);
  macsim::dds::Reader<nm::Odometry_PubSubType> odom(
      p, odom_topic, QosFamily::Sensor, [&](const nm::Odometry_& o) {
        std::lock_guard<std::mutex> lock(mutex);
        matched_odom = true;
        if (sent && o.twist().twist().linear().x() * direction > 0) {
          us.push_back(micros_since(*sent));
          sent.reset();
          seen.notify_all();
        }
      });
  for (int i = 0; i < 200 && cmd.matched() == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  for (int i = 0; i < trials + 10; ++i) {
    cmd.write(macsim::dds::planar_twist(0.0, 0.0));
    std::this_thread::sleep_for(std::chrono::milliseconds(40));  // at rest again
    std::unique_lock<std::mutex> lock(mutex);
    direction = i % 2 ? -1.0 : 1.0;
    sent = Clock::now();
    cmd.write(macsim::dds::planar_twist(0.2 * direction, 0.0));
    if (!seen.wait_for(lock, std::chrono::seconds(2), [&] { return !sent; })) {
      std::fprintf(stderr, "bench_dds: no odometry answered a twist\n");
      sent.reset();
    }
  }
  std::lock_guard<std::mutex> lock(mutex);
  if (us.size() > 10) us.erase(us.begin(), us.begin() + 10);  // warm-up
  return us;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--help") {
    std::printf(
        "usage: bench_dds [--domain N] [ROUND_TRIPS] [round_trips|images]\n"
        "  (default 1000 round trips, both parts; run from the repository root)\n"
        "  --domain N  the first of the seven DDS domains it uses, N..N+6 (default 1 + pid %% "
        "3: 1-9, below the tests' 100-232)\n"
        "  --help      this text\n");
    return 0;
  }
  // The shipped loopback + shared-memory profile, for this process and every child, unless the
  // caller chose one.
  if (!std::getenv("FASTRTPS_DEFAULT_PROFILES_FILE")) {
    setenv("FASTRTPS_DEFAULT_PROFILES_FILE", "deploy/dds/localhost.xml", 1);
  }
  if (argc > 2 && std::string(argv[1]) == "--pong") pong(std::atoi(argv[2]));
  if (argc > 2 && std::string(argv[1]) == "--images") image_source(std::atoi(argv[2]));
  int domain = 1 + getpid() % 3;
  if (argc > 2 && std::string(argv[1]) == "--domain") {
    domain = std::atoi(argv[2]);
    if (domain < 0 || domain + 6 > macsim::dds::kMaxDomainId) {
      std::fprintf(stderr, "bench_dds: --domain takes 0..%d\n", macsim::dds::kMaxDomainId - 6);
      return 2;
    }
    argv += 2;
    argc -= 2;
  }
  int n = 1000;
  if (argc > 1) {
    char* end = nullptr;
    n = static_cast<int>(std::strtol(argv[1], &end, 10));
    if (*end != '\0' || n <= 0) {
      std::fprintf(stderr, "bench_dds: ROUND_TRIPS must be a positive number, not '%s' (--help)\n",
                   argv[1]);
      return 2;
    }
  }
  const std::string only = argc > 2 ? argv[2] : "";
  if (argc > 3 || (!only.empty() && only != "round_trips" && only != "images")) {
    std::fprintf(stderr, "bench_dds: the part is round_trips or images (--help)\n");
    return 2;
  }
  std::printf("profile %s\n", std::getenv("FASTRTPS_DEFAULT_PROFILES_FILE"));
  const bool round_trips_wanted = only.empty() || only == "round_trips";
  const bool images_wanted = only.empty() || only == "images";
  const std::string bin = std::filesystem::canonical("/proc/self/exe").parent_path().string();
  auto start_macsim = [&](int offset, const std::string& world, std::vector<std::string> extra) {
    std::vector<std::string> args{
        bin + "/macsim", "--world", world,    "--domain", std::to_string(domain + offset),
        "--cameras",     "off",     "--quiet"};  // its diagnostics would go to our stderr
    args.insert(args.end(), extra.begin(), extra.end());
    return spawn(args);
  };

  // 1-3. Request/reply round trips, all servers running at once and the exchanges taken in
  //      turn (interleave()): the bare baseline (the same payload types through a plain echo
  //      process), the supervisor against macsim in real time on the small room (one operation
  //      executed per call), and lock-step Step(1) at a 1 ms step on a nearly empty world (the
  //      protocol's cost) and on the small room with the KURT3D (its physics, sensors and
  //      publishing).
  std::vector<double> bare_twist;
  if (round_trips_wanted) {
    std::vector<std::unique_ptr<macsim::process::ChildProcess>> servers;
    servers.push_back(spawn({bin + "/bench_dds", "--pong", std::to_string(domain)}));
    servers.push_back(start_macsim(1, "worlds/small_room.xml", {}));
    servers.push_back(start_macsim(2, "bench/worlds/empty_floor.xml", {"--lockstep"}));
    servers.push_back(start_macsim(6, "worlds/small_room.xml", {"--lockstep"}));
    macsim::dds::Participant bare_p({domain, "", "bench_ping"});
    macsim::client::RequestReply<mm::SupervisorRequest_PubSubType, mm::SupervisorReply_PubSubType>
        ping(bare_p, "bench/ping", "bench/pong", "bench");
    macsim::dds::Participant supervisor_p({domain + 1, "", "bench_supervisor"});
    macsim::client::SupervisorClient supervisor(supervisor_p);
    macsim::dds::Participant empty_p({domain + 2, "", "bench_lockstep"});
    macsim::client::SimulationClient empty(empty_p);
    macsim::dds::Participant room_p({domain + 6, "", "bench_lockstep"});
    macsim::client::SimulationClient room(room_p);
    for (bool ready : {ping.wait_for_server(std::chrono::seconds(20)),
                       supervisor.wait_for_server(std::chrono::seconds(20)),
                       empty.wait_for_server(std::chrono::seconds(20)),
                       room.wait_for_server(std::chrono::seconds(20))}) {
      if (!ready) std::fprintf(stderr, "bench_dds: a server did not appear\n");
    }
    const auto request = macsim::client::supervisor::get_object(1);
    std::vector<Exchange> exchanges{
        {"bare_ping_pong_rtt",
         [&] { return ping.call({}, std::chrono::seconds(5)).has_value(); },
         {}},
        {"supervisor_rtt", [&] { return supervisor.call(request).has_value(); }, {}},
        {"lockstep_step1_rtt.empty_floor", [&] { return empty.step(1).has_value(); }, {}},
        {"lockstep_step1_rtt.small_room", [&] { return room.step(1).has_value(); }, {}}};
    interleave(exchanges, n);
    // The twist baseline: the echo process answers a twist with an odometry message.
    bare_twist = twist_to_odometry(bare_p, "bench/cmd_vel", "bench/odom", std::max(100, n / 2));
    for (const auto& server : servers) server->stop();
    const std::vector<double>& bare = exchanges[0].us;
    for (const Exchange& e : exchanges) {
      report(e.name, e.us);
      if (&e != &exchanges[0]) ratio(e.name, e.us, bare);
    }
    report("bare_twist_odometry_rtt", bare_twist);

    // 4. Twist -> macsim applies it at its next 1 ms step -> odometry of that step (encoder
    //    frames every step in this world) -> received. Goal: p99 <= bare p99 + one step.
    {
      const auto macsim = start_macsim(3, "bench/worlds/kurt_1khz_encoders.xml", {"--realtime"});
      macsim::dds::Participant p({domain + 3, "", "bench_twist"});
      const auto twist = twist_to_odometry(p, macsim::dds::topics::cmd_vel("kurt"),
                                           macsim::dds::topics::odom("kurt"), std::max(100, n / 2));
      macsim->stop();
      report("twist_to_odometry", twist);
      std::printf("twist_to_odometry.p99_minus_bare_p99 %.1f us (goal <= one step, 1000 us)\n",
                  percentile(twist, 0.99) - percentile(bare_twist, 0.99));
    }

  }  // round trips
  if (!images_wanted) return 0;

  // 5. The images' bare baseline: DDS delivery alone, write to callback.
  {
    const auto source = spawn({bin + "/bench_dds", "--images", std::to_string(domain + 5)});
    macsim::dds::Participant p({domain + 5, "", "bench_image_sink"});
    std::mutex mutex;
    std::vector<double> latency;
    macsim::dds::Reader<sm::Image_PubSubType> reader(
        p, "bench/image", QosFamily::Sensor, [&](const sm::Image_& image) {
          const double now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
          std::lock_guard<std::mutex> lock(mutex);
          latency.push_back((now - macsim::dds::to_seconds(image.header().stamp())) * 1e6);
        });
    std::this_thread::sleep_for(std::chrono::seconds(6));
    source->stop();
    std::lock_guard<std::mutex> lock(mutex);
    std::printf("bare_images_640x480.received %zu of about %d\n", latency.size(), 30 * 6);
    if (latency.size() > 10) latency.erase(latency.begin(), latency.begin() + 10);
    report("bare_images_640x480.latency", latency);
  }

  // 6. Stereo images 640x480 at 30 Hz in real time: the rate they arrive at and their latency.
  //    Stamps are sim time, which runs with the wall clock from an unknown offset; odometry of
  //    the same run (published right after its step) gives that offset: its smallest
  //    arrival - stamp is the step's wall time plus one small sample's transport, so image
  //    latency = arrival - stamp - that offset (from the end of the step that was rendered,
  //    short by one small sample's transport, about 30-50 us).
  {
    const auto macsim = spawn({bin + "/macsim", "--world", "worlds/DemoWorld_v1.xml", "--domain",
                               std::to_string(domain + 4), "--cameras", "640x480", "--camera-rate",
                               "30", "--quiet"});
    macsim::dds::Participant p({domain + 4, "", "bench_images"});
    std::mutex mutex;
    std::map<std::string, std::vector<std::pair<double, double>>> images;  // eye: wall s, stamp s
    double odom_offset = 1e9;
    const auto t0 = Clock::now();
    auto wall = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    std::vector<std::unique_ptr<macsim::dds::Reader<sm::Image_PubSubType>>> readers;
    for (const std::string eye : {"left", "right"}) {
      readers.push_back(std::make_unique<macsim::dds::Reader<sm::Image_PubSubType>>(
          p, macsim::dds::topics::image("kurt", eye), QosFamily::Sensor,
          [&, eye](const sm::Image_& image) {
            const double now = wall();
            std::lock_guard<std::mutex> lock(mutex);
            images[eye].emplace_back(now, macsim::dds::to_seconds(image.header().stamp()));
          }));
    }
    macsim::dds::Reader<nm::Odometry_PubSubType> odom(
        p, macsim::dds::topics::odom("kurt"), QosFamily::Sensor, [&](const nm::Odometry_& o) {
          const double now = wall();
          std::lock_guard<std::mutex> lock(mutex);
          odom_offset = std::min(odom_offset, now - macsim::dds::to_seconds(o.header().stamp()));
        });
    std::this_thread::sleep_for(std::chrono::seconds(8));
    macsim->stop();
    std::lock_guard<std::mutex> lock(mutex);
    for (auto& [eye, arrivals] : images) {
      const std::string name = "images_640x480." + eye;
      if (arrivals.size() < 30) {
        std::printf("%s.rate %.1f Hz (too few images)\n", name.c_str(), arrivals.size() / 8.0);
        continue;
      }
      arrivals.erase(arrivals.begin(), arrivals.begin() + 10);  // start-up
      const double span = arrivals.back().first - arrivals.front().first;
      std::printf("%s.rate %.1f Hz\n", name.c_str(), (arrivals.size() - 1) / span);
      int missing = 0;  // stamps 1/30 s apart: a wider gap is a frame not rendered or lost
      for (std::size_t i = 1; i < arrivals.size(); ++i)
        missing +=
            static_cast<int>(std::lround((arrivals[i].second - arrivals[i - 1].second) * 30.0)) - 1;
      std::printf("%s.missing %d frames of %d\n", name.c_str(), missing,
                  missing + static_cast<int>(arrivals.size()));
      std::vector<double> latency;
      for (const auto& [arrival, stamp] : arrivals)
        latency.push_back((arrival - stamp - odom_offset) * 1e6);
      report(name + ".latency", latency);
    }
  }
  return 0;
}
