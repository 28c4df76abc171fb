// my_controller: the smallest controller of one's own, built against the installed SDK. Drives
// the robot forward by a distance measured by its odometry and stops, against the simulator or
// the real KURT3D alike.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "macsim/client/robot_client.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{0, "", "my_controller"};
  double distance = 0.5;
  macsim::dds::CommandLine cli("my_controller",
                               "Drives the KURT3D forward by a distance (odometry), then stops.\n"
                               "Exit 0: arrived; 1: not within 60 s; 2: usage or no robot.");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.option("distance", "METERS", "how far (default 0.5)", &distance);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (!(distance > 0 && distance < 100)) {
    macsim::log::error("my_controller: --distance must be in (0, 100) m");
    return 2;
  }

  macsim::dds::Participant dds(participant);
  macsim::client::RobotClient robot(dds, "kurt");
  const auto start = robot.wait_for_odometry(std::chrono::seconds(15));
  if (!start) {
    macsim::log::error("my_controller: no robot on DDS domain {}", participant.domain);
    return 2;
  }
  const auto& p0 = start->pose().pose().position();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  double travelled = 0.0;
  while (travelled < distance) {
    if (std::chrono::steady_clock::now() > deadline) {
      robot.stop();
      macsim::log::error("my_controller: travelled {:.3f} of {:.3f} m in 60 s", travelled,
                         distance);
      return 1;
    }
    robot.drive(0.3, 0.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (const auto odom = robot.latest_odometry()) {
      const auto& p = odom->pose().pose().position();
      travelled = std::hypot(p.x() - p0.x(), p.y() - p0.y());
    }
  }
  robot.stop();
  robot.wait_delivered();
  std::printf("my_controller: travelled %.3f m by odometry\n", travelled);
  return 0;
}
