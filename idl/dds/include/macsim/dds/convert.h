// Conversions between plain numbers and the ROS 2 message types (time, quaternions, ...).
#pragma once

#include <cmath>
#include <cstdint>

#include "macsim/msg/builtin_interfaces.h"
#include "macsim/msg/geometry_msgs.h"
#include "macsim/msg/nav_msgs.h"
#include "macsim/msg/std_msgs.h"

#include <string>

namespace macsim::dds {

/// Seconds (sim or wall) to builtin_interfaces/Time, rounded to the nanosecond.
inline builtin_interfaces::msg::dds_::Time_ to_time(double seconds) {
  const auto ns = static_cast<int64_t>(std::llround(seconds * 1e9));
  builtin_interfaces::msg::dds_::Time_ t;
  t.sec(static_cast<int32_t>(ns / 1000000000));
  t.nanosec(static_cast<uint32_t>(ns % 1000000000));
  return t;
}

/// builtin_interfaces/Time to seconds.
inline double to_seconds(const builtin_interfaces::msg::dds_::Time_& t) {
  return t.sec() + t.nanosec() * 1e-9;
}

/// A header with a stamp (s) and a frame.
inline std_msgs::msg::dds_::Header_ header(double stamp, const std::string& frame) {
  std_msgs::msg::dds_::Header_ h;
  h.stamp(to_time(stamp));
  h.frame_id(frame);
  return h;
}

inline geometry_msgs::msg::dds_::Vector3_ vector3(double x, double y, double z) {
  geometry_msgs::msg::dds_::Vector3_ v;
  v.x(x);
  v.y(y);
  v.z(z);
  return v;
}

inline geometry_msgs::msg::dds_::Point_ point(double x, double y, double z) {
  geometry_msgs::msg::dds_::Point_ p;
  p.x(x);
  p.y(y);
  p.z(z);
  return p;
}

inline geometry_msgs::msg::dds_::Quaternion_ quaternion(double x, double y, double z, double w) {
  geometry_msgs::msg::dds_::Quaternion_ q;
  q.x(x);
  q.y(y);
  q.z(z);
  q.w(w);
  return q;
}

/// Rotation by `yaw` rad about z.
inline geometry_msgs::msg::dds_::Quaternion_ yaw_quaternion(double yaw) {
  return quaternion(0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2));
}

/// Yaw (rad, about z) of a quaternion.
inline double yaw_of(const geometry_msgs::msg::dds_::Quaternion_& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()),
                    1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

/// A geometry_msgs/Twist with linear x and angular z (what a skid-steer robot obeys).
inline geometry_msgs::msg::dds_::Twist_ planar_twist(double linear, double angular) {
  geometry_msgs::msg::dds_::Twist_ t;
  t.linear(vector3(linear, 0.0, 0.0));
  t.angular(vector3(0.0, 0.0, angular));
  return t;
}

/// The odometry covariance the real KURT driver publishes (kurt_base populateCovariance,
/// default parameters: x_stddev 0.002, rotation_stddev 0.017, cross terms 0).
void set_driver_covariance(nav_msgs::msg::dds_::Odometry_& msg, double linear, double angular);

}  // namespace macsim::dds
