// The project's wire types as Fast DDS dynamic types, built from the IDL's type objects, and a
// type support that carries serialized samples unchanged (for tools handling any topic).
#pragma once

#include <fastrtps/types/DynamicPubSubType.h>
#include <fastrtps/types/DynamicTypePtr.h>

#include <cstdint>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <memory>
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

/// One sample as it travels: the 4-byte encapsulation header, then the CDR body.
struct RawSample {
  std::vector<std::uint8_t> bytes;
};

/// Type support for RawSample under any type name: samples pass through unchanged. With the
/// IDL's dynamic type of that name, keyed topics work too (the key is read from the sample).
class RawType : public eprosima::fastdds::dds::TopicDataType {
 public:
  /// `dynamic` may be null: then the topic is taken as unkeyed.
  RawType(const std::string& type_name, eprosima::fastrtps::types::DynamicType_ptr dynamic);
  ~RawType() override;

  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override;
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override;
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override;
  void* createData() override;
  void deleteData(void* data) override;
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle,
              bool force_md5) override;

 private:
  std::unique_ptr<eprosima::fastrtps::types::DynamicPubSubType> dynamic_;
};

}  // namespace macsim::dds
