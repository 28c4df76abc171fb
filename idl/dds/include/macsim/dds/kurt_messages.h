// The KURT's robot messages as its real driver (kurt_base) fills them: one source for the
// simulator's bridge and the real robot's adapter, so both publish the same data the same way.
#pragma once

#include <string>

#include "macsim/msg/nav_msgs.h"
#include "macsim/msg/sensor_msgs.h"

namespace macsim::dds {

/// Odometry in odom -> base_footprint (REP-105) with the driver's covariance.
nav_msgs::msg::dds_::Odometry_ kurt_odometry(double x, double y, double yaw, double linear,
                                             double angular, double stamp);
/// The six wheel joints; each side's three wheels share the side's angle (rad).
sensor_msgs::msg::dds_::JointState_ kurt_wheel_joints(double left, double right, double stamp);
/// The rotunit's joint state (laser_rot_joint: angle and speed), published on joint_states.
sensor_msgs::msg::dds_::JointState_ kurt_rotunit_joint(double angle, double speed, double stamp);
/// IMU in base_link: yaw (and tilt) as orientation with the yaw variance, the yaw rate; the
/// other covariances marked unknown (-1), as the driver does.
sensor_msgs::msg::dds_::Imu_ kurt_imu(double roll, double pitch, double yaw, double yaw_variance,
                                      double yaw_rate, double stamp);
/// One IR (or sonar) range in the sensor's frame, with the KURT's sensor limits.
sensor_msgs::msg::dds_::Range_ kurt_range(const std::string& frame, bool sonar, double range,
                                          double stamp);

}  // namespace macsim::dds
