// Topic names of MACSim-DDS, in the ROS 2 convention (rt/ prefix, robot namespace).
#pragma once

#include <string>

namespace macsim::dds::topics {

/// The simulation clock (rosgraph_msgs/Clock).
inline const std::string kClock = "rt/clock";

/// rt/<robot>/<name>: a topic of one robot.
inline std::string robot(const std::string& robot_name, const std::string& name) {
  return "rt/" + robot_name + "/" + name;
}

/// Velocity command (geometry_msgs/Twist), as the real driver's cmd_vel.
inline std::string cmd_vel(const std::string& robot_name) { return robot(robot_name, "cmd_vel"); }
/// Wheel odometry (nav_msgs/Odometry), as the real driver computes it from encoder ticks.
inline std::string odom(const std::string& robot_name) { return robot(robot_name, "odom"); }
/// Simulator-only ground truth pose and velocity of base_footprint (nav_msgs/Odometry).
inline std::string ground_truth(const std::string& robot_name) {
  return robot(robot_name, "ground_truth");
}

}  // namespace macsim::dds::topics
