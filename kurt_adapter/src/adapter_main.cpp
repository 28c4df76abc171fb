// kurt_adapter: the real KURT3D as a DDS participant. Speaks the robot's CAN protocol
// (SocketCAN, or the userspace UDP bus) and serves the robot topics macsim serves for a KURT,
// with the same names, types, QoS and frames, so a controller cannot tell them apart.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <thread>

#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"
#include "macsim/dds/participant.h"
#include "macsim/dds/topics.h"
#include "macsim/kurt/kurt_driver.h"
#include "macsim/kurt/real_kurt.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/robot/robot_node.h"
#include "macsim/robot/command_queue.h"

namespace {

namespace mm = macsim_msgs::msg::dds_;
using macsim::dds::QosFamily;
using Clock = std::chrono::steady_clock;
using namespace macsim::kurt;

/// What SIM_FEATURES answers: a robot, not a simulator.
constexpr const char* kFeatures = "robot,kurt3d,odometry,range,imu,rotunit,magnet_actuator";

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }

/// Sends the hard stop, retrying for up to 200 ms while the bus refuses it (a full SocketCAN
/// queue answers ENOBUFS), as the real driver insists; false (and says so) if it never went.
bool hard_stop(CanTransport& can) {
  const auto give_up = Clock::now() + std::chrono::milliseconds(200);
  while (!can.send(encode_hard_stop())) {
    if (Clock::now() > give_up) {
      macsim::log::error(
          "kurt_adapter: the bus refused the hard stop for 200 ms: STOP THE ROBOT BY HAND");
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

double seconds(Clock::time_point t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}
/// Message stamps: wall-clock time, as the real driver stamps with ROS time.
double wall_stamp() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

/// Commands for the robot, queued by DDS callbacks and run on the CAN loop's thread.
using CommandQueue = macsim::BasicCommandQueue<macsim::robot::RobotInterface&>;

}  // namespace

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{0, "", "kurt_adapter"};
  std::string can_spec = "socketcan:can0";
  std::string robot = "kurt";
  macsim::dds::CommandLine cli(
      "kurt_adapter",
      "The real KURT3D on DDS: its CAN protocol on one side, the robot topics macsim serves on\n"
      "the other (cmd_vel, wheel_speeds, rot_vel, crane/magnet in; odom, joint_states, imu,\n"
      "range out). SPEED_CM every 10 ms; zero speed 0.6 s after the last command; a hard stop\n"
      "on exit (SIGINT, SIGTERM).");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.option("can", "BUS",
             "socketcan:IFACE (the robot, default socketcan:can0) or udp:LOCAL_PORT:PEER_PORT "
             "(the userspace bus, e.g. with kurt_emulator)",
             &can_spec);
  cli.option("robot", "NAME", "the robot's topic namespace (default kurt)", &robot);
  macsim::robot::NodeOptions node_options;
  cli.option("frame-prefix", "PREFIX",
             "put PREFIX before every frame id (e.g. kurt/: kurt/odom, kurt/base_link)",
             &node_options.frame_prefix);
  cli.flag("cmd-vel-stamped",
           "take cmd_vel as geometry_msgs/TwistStamped (Nav2 from ROS 2 Kilted on), not Twist",
           &node_options.cmd_vel_stamped);
  // The real driver's parameters; the defaults are the indoor KURT's (kurt_base), the outdoor
  // one has --wheel-perimeter 0.518 --axis-length 0.39 --turning-adaptation 0.64.
  macsim::KurtDriveParams params;
  auto fallback = [](auto value) { return fmt::format(" (default {})", value); };
  cli.option("wheel-perimeter", "M", "wheel perimeter" + fallback(params.wheel_perimeter),
             &params.wheel_perimeter);
  cli.option("axis-length", "M", "track of cmd_vel and odometry" + fallback(params.axis_length),
             &params.axis_length);
  cli.option("turning-adaptation", "FACTOR",
             "odometry's skid factor" + fallback(params.turning_adaptation),
             &params.turning_adaptation);
  cli.option("ticks-per-turn", "N", "encoder ticks per wheel turn" + fallback(params.ticks_per_turn),
             &params.ticks_per_turn);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (!(params.wheel_perimeter > 0) || !(params.axis_length > 0) ||
      !(params.turning_adaptation > 0) || params.ticks_per_turn <= 0) {
    macsim::log::error(
        "kurt_adapter: --wheel-perimeter, --axis-length, --turning-adaptation and "
        "--ticks-per-turn must be positive");
    return 2;
  }

  std::unique_ptr<CanTransport> can;
  try {
    can = open_can(can_spec);
  } catch (const CanError& e) {
    macsim::log::error("kurt_adapter: {}", e.what());
    return 1;
  }
  // Every way a terminal or a supervisor ends us is a stop with a hard stop first.
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGQUIT})
    std::signal(signal_number, on_signal);

  try {
    macsim::dds::Participant dds(participant);
    CommandQueue queue;
    KurtDriver driver(params);
    RealKurt kurt(
        robot, driver, *can, [] { return seconds(Clock::now()); }, wall_stamp);
    // The one robot node: the topics of what the robot has; callbacks only queue, and the CAN
    // loop runs the commands at its next 10 ms tick.
    macsim::robot::RobotNode node(
        dds, kurt,
        [&queue, &robot](macsim::robot::RobotCommand command, const macsim::dds::SampleId&) {
          queue.push([command = std::move(command), &robot](macsim::robot::RobotInterface& real) {
            if (!real.execute(command)) {
              macsim::log::warn("kurt_adapter: robot '{}' has no command '{}': refused", robot,
                                command.name());
            }
          });
        },
        node_options);

    // The simulation control topic: a real robot answers SIM_FEATURES only (macsim_msgs.idl), so
    // a simulator on the same domain stays the only one answering the rest.
    macsim::dds::Writer<mm::SimulationReply_PubSubType> sim_replies(
        dds, macsim::dds::topics::kSimulationReply, QosFamily::Request);
    macsim::dds::Reader<mm::SimulationRequest_PubSubType> sim_requests(
        dds, macsim::dds::topics::kSimulationRequest, QosFamily::Request,
        [&](const mm::SimulationRequest_& request) {
          if (request.command() != mm::SIM_FEATURES) return;
          queue.push([&sim_replies, request](macsim::robot::RobotInterface&) {
            mm::SimulationReply_ reply;
            reply.client_id(request.client_id());
            reply.sequence_number(request.sequence_number());
            reply.code(mm::ERR_OK);
            reply.features(kFeatures);
            sim_replies.write(reply);  // a repeat is answered again: this has no effects
          });
        });

    std::cout << "kurt_adapter: CAN bus " << can_spec << "; serving on DDS domain "
              << participant.domain << ":\n";
    for (const auto& line : node.topic_lines()) std::cout << "  " << line << "\n";
    std::cout << "  " << macsim::dds::topics::kSimulationRequest
              << " (macsim_msgs/SimulationRequest, in: SIM_FEATURES)\n  "
              << macsim::dds::topics::kSimulationReply << " (macsim_msgs/SimulationReply, out)\n";
    std::cout << "kurt_adapter: not on this robot:";
    for (const auto& topic : node.lacking_topics()) std::cout << " " << topic;
    std::cout << "\n";
    std::cout << std::flush;

    auto next_tick = Clock::now();
    while (!g_stop.load()) {
      // Frames from the robot until the next 10 ms tick; each one's readings go out at once.
      while (true) {
        const auto wait =
            std::chrono::duration_cast<std::chrono::milliseconds>(next_tick - Clock::now());
        auto frame = can->receive(std::max(wait, std::chrono::milliseconds(0)));
        if (!frame) break;
        kurt.handle(*frame);
        node.publish();
        if (Clock::now() >= next_tick) break;
      }
      // The tick: commands, then the set-point (zero once the last command is 0.6 s old).
      node.poll_commands();
      queue.drain(kurt);
      can->send(driver.control_frame(seconds(Clock::now())));
      next_tick += std::chrono::milliseconds(10);
      if (Clock::now() > next_tick + std::chrono::milliseconds(100)) next_tick = Clock::now();
    }
    // Exit: the robot must not roll on. Hard stop first, then the rotunit to rest.
    if (!hard_stop(*can)) return 4;
    can->send(driver.command_rotunit(0.0));
    std::cout << "kurt_adapter: hard stop sent, exiting" << std::endl;
  } catch (const macsim::dds::DdsError& e) {
    hard_stop(*can);
    macsim::log::error("kurt_adapter: DDS error: {}", e.what());
    return 3;
  } catch (const std::exception& e) {
    hard_stop(*can);
    macsim::log::error("kurt_adapter: {}", e.what());
    return 3;
  }
  return 0;
}
