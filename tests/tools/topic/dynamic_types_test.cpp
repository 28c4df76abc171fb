// The IDL's types as dynamic types, and names between DDS and ROS.
#include "macsim/dds/dynamic_types.h"

#include <gtest/gtest.h>

#include <algorithm>


namespace macsim::dds {
namespace {

TEST(DynamicTypes, EveryIdlTypeIsThereByItsDdsName) {
  const auto& names = idl_type_names();
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  for (const char* n : {"nav_msgs::msg::dds_::Odometry_", "sensor_msgs::msg::dds_::Image_",
                        "macsim_msgs::msg::dds_::SupervisorRequest_",
                        "kurt_msgs::msg::dds_::CraneState_", "rosgraph_msgs::msg::dds_::Clock_"}) {
    EXPECT_TRUE(std::binary_search(names.begin(), names.end(), n)) << n;
    EXPECT_TRUE(idl_dynamic_type(n)) << n;
  }
  EXPECT_FALSE(idl_dynamic_type("nav_msgs::msg::dds_::Odometry"));
  EXPECT_FALSE(idl_dynamic_type("Odometry_"));
}

TEST(DynamicTypes, NamesTranslateBetweenDdsAndRos) {
  EXPECT_EQ(ros_type_name("nav_msgs::msg::dds_::Odometry_"), "nav_msgs/msg/Odometry");
  EXPECT_EQ(dds_type_name("nav_msgs/msg/Odometry"), "nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(dds_type_name("nav_msgs/Odometry"), "nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(dds_type_name("nav_msgs::msg::dds_::Odometry_"), "nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(ros_type_name("plain"), "plain");
  EXPECT_EQ(ros_topic_name("rt/kurt/odom"), "/kurt/odom");
  EXPECT_EQ(ros_topic_name("ros_discovery_info"), "");
  EXPECT_EQ(dds_topic_name("/kurt/odom"), "rt/kurt/odom");
  EXPECT_EQ(dds_topic_name("kurt/odom"), "rt/kurt/odom");
  EXPECT_EQ(dds_topic_name("rt/kurt/odom"), "rt/kurt/odom");
  EXPECT_EQ(dds_topic_name("rq/resetRequest"), "rq/resetRequest");
}

}  // namespace
}  // namespace macsim::dds
