// The controller's handle on one KURT3D over DDS: the same topics whether a simulator or the
// real robot's adapter serves them.
#pragma once

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "macsim/client/commands_sent.h"
#include "macsim/dds/participant.h"
#include "macsim/msg/geometry_msgs.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/kurt_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgs.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"

namespace macsim::client {

/// Sends velocity commands to a robot and keeps its latest odometry.
class RobotClient {
 public:
  using Odometry = nav_msgs::msg::dds_::Odometry_;

  /// `reading`: the QoS family of its odometry reader, as Crane's (robot_devices.h).
  RobotClient(dds::Participant& participant, const std::string& robot_name,
              dds::QosFamily reading = dds::QosFamily::Sensor);

  /// Publishes a velocity command (m/s forward, rad/s counter-clockwise) on cmd_vel.
  /// The robot stops by itself 0.6 s after the last command, so repeat it while moving.
  bool drive(double linear, double angular);
  /// Publishes left and right wheel rim speeds (m/s) on wheel_speeds, the alternative to a
  /// twist (the same 0.6 s timeout).
  bool drive_wheels(double left, double right);
  /// Waits until the robot's participant has received every command sent so far (lock-step
  /// needs no such wait: a step request names the commands sent before it).
  bool wait_delivered(std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    return cmd_vel_.wait_acknowledged(timeout) && wheel_speeds_.wait_acknowledged(timeout);
  }
  /// Publishes a zero velocity command.
  bool stop() { return drive(0.0, 0.0); }

  /// Waits until an odometry sample newer than the last one returned arrives.
  std::optional<Odometry> wait_for_odometry(std::chrono::milliseconds timeout);
  /// What next_odometry() found.
  struct Next {
    std::optional<Odometry> odometry;  ///< nothing: the robot did not come back in time
    bool returned = false;  ///< the first odometry after an outage (it may start from zero)
  };
  /// The next odometry, riding out an outage: when none comes within `silence`, it says so on
  /// stderr (the robot went silent: a simulator killed or restarted, the adapter gone), and
  /// waits up to `patience` more for the robot to serve again, then says that too.
  Next next_odometry(std::chrono::milliseconds silence, std::chrono::milliseconds patience);
  /// The latest odometry received, if any.
  std::optional<Odometry> latest_odometry() const;
  /// Forgets the odometry received so far (after a world reset sim time starts again, so
  /// stamps repeat).
  void forget_odometry();
  /// Odometry writers matched so far, those gone included (a simulator restarted brings a new
  /// one).
  int odometry_writers_seen() const { return odom_.matched_ever(); }
  /// True once a participant serving this robot's cmd_vel has been matched.
  bool commander_matched() const { return cmd_vel_.matched() > 0; }
  /// Readers its cmd_vel writer has matched (a killed simulator's count until its lease runs
  /// out).
  int command_readers() const { return cmd_vel_.matched(); }
  /// Readers its cmd_vel writer matched so far, those gone included.
  int command_readers_seen() const { return cmd_vel_.readers_seen(); }

  const std::string& robot_name() const { return robot_name_; }

 private:
  std::string robot_name_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::optional<Odometry> latest_;
  uint64_t received_ = 0, returned_ = 0;
  CommandWriter<geometry_msgs::msg::dds_::Twist_PubSubType> cmd_vel_;
  CommandWriter<kurt_msgs::msg::dds_::WheelSpeeds_PubSubType> wheel_speeds_;
  dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType> odom_;
};

}  // namespace macsim::client
