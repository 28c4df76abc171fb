// bench_client: the C++ client library's side of the Python comparison (bench/python_client.py
// starts it once and asks it for blocks of samples in turn with its own, against the same
// servers). Prints one `<part> <microseconds>` line per sample:
//   supervisor  a get_object round trip (the request of bench_dds's supervisor_rtt);
//   step        a lock-step Step(1) round trip;
//   image       arrival of a 640x480 image as a cv::Mat (BGR) minus its send stamp.
// --image-source publishes those images (bgr8, 30 Hz, stamped on the steady clock, which is
// CLOCK_MONOTONIC in every process) as robot kurt's left camera until stopped.
#include <chrono>
#include <cstdio>
#include <optional>
#include <thread>

#include "image_source.h"
#include "macsim/client/robot_devices.h"
#include "macsim/client/supervisor_client.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"

namespace {

using Clock = std::chrono::steady_clock;
namespace sm = sensor_msgs::msg::dds_;

double now_seconds() {
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

double micros_since(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{0, "", "bench_client"};
  int object = 1;
  bool source = false;
  macsim::dds::CommandLine cli(
      "bench_client",
      "The C++ client library's round trips and image latency. Reads `<part> <count>` lines\n"
      "(part: supervisor, step or image) and answers each with one `<part> <us>` line per\n"
      "sample and an `end` line; bench/python_client.py drives it.");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.option("object", "ID", "the object get_object asks for (default 1)", &object);
  cli.flag("image-source", "publish 640x480 images at 30 Hz as kurt's left camera", &source);
  if (auto code = cli.parse(argc, argv)) return *code;
  macsim::dds::Participant p(participant);
  if (source) macsim::bench::publish_images(p, macsim::dds::topics::image("kurt", "left"));

  // One long-lived participant and its clients, like the Python side's.
  macsim::client::SupervisorClient supervisor(p);
  macsim::client::SimulationClient simulation(p);
  if (!supervisor.wait_for_server(std::chrono::seconds(20)) ||
      !simulation.wait_for_server(std::chrono::seconds(20))) {
    std::fprintf(stderr, "bench_client: no macsim on domain %d\n", participant.domain);
    return 1;
  }
  const auto request = macsim::client::supervisor::get_object(static_cast<uint32_t>(object));
  std::printf("ready\n");
  std::fflush(stdout);
  char part[32];
  int count = 0;
  while (std::scanf("%31s %d", part, &count) == 2) {
    const std::string what = part;
    // Images: a reader of this block only, so that one side at a time takes them.
    std::optional<macsim::client::StereoCamera> cameras;
    if (what == "image") {
      cameras.emplace(p, "kurt");
      if (!cameras->eye("left").wait_shared_after(0, std::chrono::seconds(20))) return 1;
    }
    for (int i = 0; i < count; ++i) {
      if (what == "supervisor") {
        const auto start = Clock::now();
        const auto reply = supervisor.call(request);
        if (!reply || reply->code() != 0) return 1;
        std::printf("supervisor %.1f\n", micros_since(start));
      } else if (what == "step") {
        const auto start = Clock::now();
        if (!simulation.step(1)) return 1;
        std::printf("step %.1f\n", micros_since(start));
      } else if (what == "image") {
        const auto& left = cameras->eye("left");
        const uint64_t seen = left.count();
        const auto image = left.wait_shared_after(seen, std::chrono::seconds(5));
        if (!image) return 1;
        const cv::Mat bgr = macsim::client::to_bgr(*image);  // what a C++ controller works on
        const double latency = now_seconds() - macsim::client::stamp_seconds(image->header());
        if (bgr.empty()) return 1;
        std::printf("image %.1f\n", latency * 1e6);
      } else {
        std::fprintf(stderr, "bench_client: unknown part '%s'\n", part);
        return 2;
      }
    }
    std::printf("end\n");
    std::fflush(stdout);
  }
  return 0;
}
