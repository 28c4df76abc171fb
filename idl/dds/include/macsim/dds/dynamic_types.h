// The project's wire types as Fast DDS dynamic types, built from the IDL's type objects (for
// tools handling any topic), and the names of types and topics between DDS and ROS.
#pragma once

#include <fastrtps/types/DynamicPubSubType.h>
#include <fastrtps/types/DynamicTypePtr.h>

#include <fastdds/dds/topic/TopicDataType.hpp>
#include <string>
#include <vector>

namespace macsim::dds {

/// Every type the IDL defines, by DDS name ("nav_msgs::msg::dds_::Odometry_"), sorted.
const std::vector<std::string>& idl_type_names();
/// The dynamic type of a DDS type name, or null if the IDL defines no such type.
eprosima::fastrtps::types::DynamicType_ptr idl_dynamic_type(const std::string& dds_name);

/// "nav_msgs/msg/Odometry" for "nav_msgs::msg::dds_::Odometry_"; the input if not of that form.
std::string ros_type_name(const std::string& dds_name);
/// "nav_msgs::msg::dds_::Odometry_" for "nav_msgs/msg/Odometry" or "nav_msgs/Odometry"; a DDS
/// name is returned as it is.
std::string dds_type_name(const std::string& ros_or_dds_name);
/// "/kurt/odom" for "rt/kurt/odom"; empty if the DDS topic is not a ROS topic (no "rt/").
std::string ros_topic_name(const std::string& dds_topic);
/// "rt/kurt/odom" for "/kurt/odom" or "kurt/odom"; a name starting "rt/", "rq/" or "rr/" stays.
std::string dds_topic_name(const std::string& ros_or_dds_topic);

}  // namespace macsim::dds
