#include "macsim/dds/kurt_messages.h"

#include <Eigen/Geometry>
#include <array>

#include "macsim/dds/convert.h"

namespace macsim::dds {

nav_msgs::msg::dds_::Odometry_ kurt_odometry(double x, double y, double yaw, double linear,
                                             double angular, double stamp) {
  nav_msgs::msg::dds_::Odometry_ msg;
  msg.header(header(stamp, "odom"));  // REP-105 (the uos driver said odom_combined)
  msg.child_frame_id("base_footprint");
  msg.pose().pose().position().x(x);
  msg.pose().pose().position().y(y);
  msg.pose().pose().orientation(yaw_quaternion(yaw));
  msg.twist().twist().linear().x(linear);
  msg.twist().twist().angular().z(angular);
  set_driver_covariance(msg, linear, angular);
  return msg;
}

sensor_msgs::msg::dds_::JointState_ kurt_wheel_joints(double left, double right, double stamp) {
  sensor_msgs::msg::dds_::JointState_ msg;
  msg.header(header(stamp, ""));
  for (const char* side : {"left", "right"}) {
    for (const char* wheel : {"front", "middle", "rear"}) {
      msg.name().push_back(std::string(side) + "_" + wheel + "_wheel_joint");
      msg.position().push_back(side[0] == 'l' ? left : right);
    }
  }
  return msg;
}

sensor_msgs::msg::dds_::JointState_ kurt_rotunit_joint(double angle, double speed, double stamp) {
  sensor_msgs::msg::dds_::JointState_ msg;
  msg.header(header(stamp, ""));
  msg.name({"laser_rot_joint"});
  msg.position({angle});
  msg.velocity({speed});
  return msg;
}

sensor_msgs::msg::dds_::Imu_ kurt_imu(double roll, double pitch, double yaw, double yaw_variance,
                                      double yaw_rate, double stamp) {
  sensor_msgs::msg::dds_::Imu_ msg;
  msg.header(header(stamp, "base_link"));
  const Eigen::Quaterniond q = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  msg.orientation(quaternion(q.x(), q.y(), q.z(), q.w()));
  std::array<double, 9> orientation_covariance{};
  orientation_covariance[8] = yaw_variance;
  msg.orientation_covariance(orientation_covariance);
  msg.angular_velocity(vector3(0, 0, yaw_rate));
  std::array<double, 9> unknown{};
  unknown[0] = -1;  // as the KURT driver: rates and accelerations are not provided
  msg.angular_velocity_covariance(unknown);
  msg.linear_acceleration_covariance(unknown);
  return msg;
}

sensor_msgs::msg::dds_::Range_ kurt_range(const std::string& frame, bool sonar, double range,
                                          double stamp) {
  // kurt.h: IR 0.10-0.80 m in a 0.07486 rad cone, ultrasound 0.10-1.00 m in 0.17809 rad.
  sensor_msgs::msg::dds_::Range_ msg;
  msg.header(header(stamp, frame));
  msg.radiation_type(sonar ? 0 : 1);
  msg.field_of_view(static_cast<float>(sonar ? 0.17809 : 0.07486));
  msg.min_range(0.10f);
  msg.max_range(sonar ? 1.00f : 0.80f);
  msg.range(static_cast<float>(range));
  return msg;
}

}  // namespace macsim::dds
