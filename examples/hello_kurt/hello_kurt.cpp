// helloKurt: the first controller. Drives the KURT 1 m forward by its odometry, over DDS,
// against whichever participant serves the robot's topics (the simulator or the real robot).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <thread>

#include "macsim/client/robot_client.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"

namespace {

double planar_distance(const macsim::client::RobotClient::Odometry& a,
                       const macsim::client::RobotClient::Odometry& b) {
  const auto& p = a.pose().pose().position();
  const auto& q = b.pose().pose().position();
  return std::hypot(p.x() - q.x(), p.y() - q.y());
}

}  // namespace

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{0, "", "helloKurt"};
  std::string robot = "kurt";
  double distance = 1.0;
  double speed = 0.3;
  double timeout = 60.0;
  double discovery_timeout = 15.0;
  double reconnect_timeout = 30.0;

  macsim::dds::CommandLine cli("helloKurt",
                               "Drives a KURT3D forward by a distance measured by its odometry, "
                               "then stops.\nExit 0: arrived; 1: timeout; 2: usage or no robot "
                               "found; 3: the robot went silent and did not come back.");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.option("robot", "NAME", "robot namespace (default kurt)", &robot);
  cli.option("distance", "METERS", "distance to drive (default 1.0)", &distance);
  cli.option("speed", "M_PER_S", "cruise speed (default 0.3)", &speed);
  cli.option("timeout", "SECONDS", "give up after this long (default 60)", &timeout);
  cli.option("discovery-timeout", "SECONDS", "wait this long for the robot (default 15)",
             &discovery_timeout);
  cli.option("reconnect-timeout", "SECONDS",
             "when the robot goes silent (a simulator restarted), wait this long for it to come "
             "back and carry on (default 30)",
             &reconnect_timeout);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (distance <= 0 || speed <= 0 || timeout <= 0 || discovery_timeout <= 0 ||
      reconnect_timeout < 0) {
    macsim::log::error("helloKurt: --distance, --speed and the timeouts must be positive");
    return 2;
  }

  try {
    macsim::dds::Participant dds(participant);
    macsim::client::RobotClient kurt(dds, robot);

    std::printf("helloKurt: looking for robot '%s' on DDS domain %d ...\n", robot.c_str(),
                participant.domain);
    auto start = kurt.wait_for_odometry(
        std::chrono::milliseconds(static_cast<int>(discovery_timeout * 1000)));
    if (!start) {
      macsim::log::error(
          "helloKurt: no odometry from robot '{}' on DDS domain {} within {:.0f} s: is macsim (or "
          "kurt_adapter) running with the same --domain and DDS profile?",
          robot, participant.domain, discovery_timeout);
      return 2;
    }
    std::printf("helloKurt: found '%s' at odometry (%.3f, %.3f); driving %.2f m at %.2f m/s\n",
                robot.c_str(), start->pose().pose().position().x(),
                start->pose().pose().position().y(), distance, speed);

    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::duration<double>(timeout);
    double next_report = 0.1;
    double travelled = 0.0;
    double before_outages = 0.0;  // travelled up to the last outage
    constexpr double kTolerance = 0.005;
    while (true) {
      auto next = kurt.next_odometry(std::chrono::milliseconds(2000),
                                     std::chrono::milliseconds(int(reconnect_timeout * 1000)));
      if (!next.odometry) {
        kurt.stop();
        macsim::log::error("helloKurt: robot '{}' went silent and did not come back", robot);
        return 3;
      }
      auto& odom = next.odometry;
      if (next.returned) {
        // Its odometry may have started again (a restarted simulator): count from here on.
        before_outages = travelled;
        start = odom;
        std::printf("helloKurt: robot '%s' is back; %.2f m to go\n", robot.c_str(),
                    distance - travelled);
      }
      travelled = before_outages + planar_distance(*odom, *start);
      const double remaining = distance - travelled;
      if (remaining <= kTolerance) break;
      if (Clock::now() > deadline) {
        kurt.stop();
        macsim::log::error(
            "helloKurt: did not arrive within {:.0f} s (travelled {:.3f} of {:.3f} m)", timeout,
            travelled, distance);
        return 1;
      }
      // Slow down near the goal; never below what SPEED_CM can express (1 cm/s steps).
      kurt.drive(std::clamp(1.5 * remaining, 0.05, speed), 0.0);
      if (travelled >= next_report) {
        std::printf("helloKurt: %.2f m  (odometry x %.3f, y %.3f, v %.2f m/s)\n", travelled,
                    odom->pose().pose().position().x(), odom->pose().pose().position().y(),
                    odom->twist().twist().linear().x());
        std::fflush(stdout);
        next_report += 0.1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }

    // Stop and wait until the odometry says the robot stands.
    for (int i = 0; i < 40; ++i) {
      kurt.stop();
      auto odom = kurt.wait_for_odometry(std::chrono::milliseconds(500));
      if (odom && std::fabs(odom->twist().twist().linear().x()) < 1e-6) {
        travelled = before_outages + planar_distance(*odom, *start);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
    std::printf("helloKurt: arrived: travelled %.3f m by odometry (goal %.3f m)\n", travelled,
                distance);
  } catch (const macsim::dds::DdsError& e) {
    macsim::log::error("helloKurt: DDS error: {}", e.what());
    return 2;
  }
  return 0;
}
