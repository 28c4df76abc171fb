// Round trips over DDS, each beside its baseline in the same run (machines here are noisy):
// a bare Fast DDS ping-pong between two processes with the supervisor's payload types, the
// supervisor's request/reply against macsim, and a lock-step Step(1) against macsim.
// Prints `name value unit` lines.   bench_dds [ROUND_TRIPS]   (from the repository root)
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <mutex>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "macsim/client/supervisor_client.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"

namespace {

namespace mm = macsim_msgs::msg::dds_;
using Clock = std::chrono::steady_clock;

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * v.size()))];
}

void report(const std::string& name, const std::vector<double>& us) {
  std::printf("%s.p50 %.1f us\n%s.p99 %.1f us\n", name.c_str(), percentile(us, 0.5), name.c_str(),
              percentile(us, 0.99));
}

/// The bare baseline's echo: every request comes back as a reply with the same correlation.
[[noreturn]] void pong(int domain) {
  macsim::dds::Participant p({domain, "", "bench_pong"});
  macsim::dds::Writer<mm::SupervisorReply_PubSubType> replies(p, "bench/pong", macsim::dds::QosFamily::Command);
  macsim::dds::Reader<mm::SupervisorRequest_PubSubType> requests(
      p, "bench/ping", macsim::dds::QosFamily::Command, [&](const mm::SupervisorRequest_& r) {
        mm::SupervisorReply_ reply;
        reply.client_id(r.client_id());
        reply.sequence_number(r.sequence_number());
        replies.write(reply);
      });
  while (true) std::this_thread::sleep_for(std::chrono::seconds(1));
}

pid_t spawn(const std::vector<std::string>& argv) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  return pid;
}

void stop(pid_t pid) {
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
}

/// Round trip times (us) of `n` calls after 50 warm-up calls.
template <class Client, class Call>
std::vector<double> round_trips(Client& client, int n, Call call) {
  client.wait_for_server(std::chrono::seconds(20));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let discovery settle both ways
  for (int i = 0; i < 50; ++i) call();
  std::vector<double> us;
  for (int i = 0; i < n; ++i) {
    const auto t0 = Clock::now();
    if (!call()) {
      std::fprintf(stderr, "bench_dds: a call got no reply\n");
      continue;
    }
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  return us;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--help") {
    std::printf("usage: bench_dds [ROUND_TRIPS]  (default 1000; run from the repository root)\n");
    return 0;
  }
  if (argc > 2 && std::string(argv[1]) == "--pong") pong(std::atoi(argv[2]));
  const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  const std::string bin = std::filesystem::canonical("/proc/self/exe").parent_path().string();
  const int domain = 200 + getpid() % 30;

  // 1. The bare baseline: the same payload types, a plain echo process.
  std::vector<double> bare;
  {
    const pid_t echo = spawn({bin + "/bench_dds", "--pong", std::to_string(domain)});
    macsim::dds::Participant p({domain, "", "bench_ping"});
    macsim::client::RequestReply<mm::SupervisorRequest_PubSubType, mm::SupervisorReply_PubSubType>
        ping(p, "bench/ping", "bench/pong", "bench");
    bare = round_trips(ping, n, [&] { return ping.call({}, std::chrono::seconds(5)).has_value(); });
    stop(echo);
  }
  report("bare_ping_pong_rtt", bare);

  // 2. The supervisor against macsim (the same types, one operation executed per call).
  std::vector<double> supervisor, step;
  {
    const pid_t macsim = spawn({bin + "/macsim", "--world", "worlds/small_room.xml", "--domain",
                                std::to_string(domain + 1), "--cameras", "off"});
    macsim::dds::Participant p({domain + 1, "", "bench_supervisor"});
    macsim::client::SupervisorClient client(p);
    const auto request = macsim::client::SupervisorClient::request(mm::OP_GET_OBJECT, 1);
    supervisor = round_trips(client, n, [&] { return client.call(request).has_value(); });
    stop(macsim);
  }
  report("supervisor_rtt", supervisor);
  std::printf("supervisor_rtt_over_bare.p50 %.2f x\n", percentile(supervisor, 0.5) / percentile(bare, 0.5));

  // 3. Lock-step: Step(1) at a 1 ms step.
  {
    const pid_t macsim = spawn({bin + "/macsim", "--world", "worlds/small_room.xml", "--domain",
                                std::to_string(domain + 2), "--cameras", "off", "--lockstep"});
    macsim::dds::Participant p({domain + 2, "", "bench_lockstep"});
    macsim::client::SimulationClient client(p);
    step = round_trips(client, n, [&] { return client.step(1).has_value(); });
    stop(macsim);
  }
  report("lockstep_step1_rtt", step);
  std::printf("lockstep_step1_rtt_over_bare.p50 %.2f x\n", percentile(step, 0.5) / percentile(bare, 0.5));

  // 4. Stereo images 640x480 at 30 Hz in real time: the rate they arrive at, and how late each
  //    is beyond the earliest one (sim time runs with the wall clock, so stamp + offset is when
  //    it was due; the smallest offset seen is rendering + transport at its best).
  {
    const pid_t macsim = spawn({bin + "/macsim", "--world", "worlds/DemoWorld_v1.xml", "--domain",
                                std::to_string(domain + 3), "--cameras", "640x480", "--camera-rate", "30"});
    macsim::dds::Participant p({domain + 3, "", "bench_images"});
    std::mutex mutex;
    std::vector<std::pair<double, double>> arrivals;  // wall s, stamp s
    const auto t0 = Clock::now();
    macsim::dds::Reader<sensor_msgs::msg::dds_::Image_PubSubType> images(
        p, macsim::dds::topics::image("kurt", "left"), macsim::dds::QosFamily::Sensor,
        [&](const sensor_msgs::msg::dds_::Image_& image) {
          const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
          std::lock_guard<std::mutex> lock(mutex);
          arrivals.emplace_back(wall, macsim::dds::to_seconds(image.header().stamp()));
        });
    std::this_thread::sleep_for(std::chrono::seconds(8));
    stop(macsim);
    std::lock_guard<std::mutex> lock(mutex);
    if (arrivals.size() > 30) {
      arrivals.erase(arrivals.begin(), arrivals.begin() + 10);  // start-up
      const double span = arrivals.back().first - arrivals.front().first;
      std::printf("images_640x480.rate %.1f Hz\n", (arrivals.size() - 1) / span);
      double best = 1e9;
      for (const auto& [wall, stamp] : arrivals) best = std::min(best, wall - stamp);
      std::vector<double> late;
      for (const auto& [wall, stamp] : arrivals) late.push_back((wall - stamp - best) * 1e6);
      report("images_640x480.latency_beyond_best", late);
    } else {
      std::printf("images_640x480.rate %.1f Hz (too few images)\n", arrivals.size() / 8.0);
    }
  }
  return 0;
}
