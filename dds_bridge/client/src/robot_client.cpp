#include "macsim/client/robot_client.h"

#include <iostream>

#include "macsim/dds/convert.h"
#include "macsim/dds/log.h"
#include "macsim/dds/topics.h"

namespace macsim::client {

RobotClient::RobotClient(dds::Participant& participant, const std::string& robot_name,
                         dds::QosFamily reading)
    : robot_name_(robot_name),
      cmd_vel_(participant, dds::topics::cmd_vel(robot_name)),
      wheel_speeds_(participant, dds::topics::wheel_speeds(robot_name)),
      odom_(participant, dds::topics::odom(robot_name), reading, [this](const Odometry& odom) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          latest_ = odom;
          ++received_;
        }
        arrived_.notify_all();
      }) {}

bool RobotClient::drive(double linear, double angular) {
  return cmd_vel_.write(dds::planar_twist(linear, angular));
}

bool RobotClient::drive_wheels(double left, double right) {
  kurt_msgs::msg::dds_::WheelSpeeds_ speeds;
  speeds.left(left);
  speeds.right(right);
  return wheel_speeds_.write(speeds);
}

std::optional<RobotClient::Odometry> RobotClient::wait_for_odometry(
    std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!arrived_.wait_for(lock, timeout, [this] { return received_ > returned_; })) {
    return std::nullopt;
  }
  returned_ = received_;
  return latest_;
}

RobotClient::Next RobotClient::next_odometry(std::chrono::milliseconds silence,
                                             std::chrono::milliseconds patience) {
  if (auto odometry = wait_for_odometry(silence)) return {odometry, false};
  log::warn(
      "macsim client: robot '{}' went silent (no odometry for {} s); waiting up to {} s for it "
      "to come back",
      robot_name_, silence.count() / 1000.0, patience.count() / 1000.0);
  auto odometry = wait_for_odometry(patience);
  if (odometry) {
    log::info("macsim client: robot '{}' is back", robot_name_);
  }
  return {odometry, odometry.has_value()};
}

std::optional<RobotClient::Odometry> RobotClient::latest_odometry() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

void RobotClient::forget_odometry() {
  std::lock_guard<std::mutex> lock(mutex_);
  latest_.reset();
}

}  // namespace macsim::client
