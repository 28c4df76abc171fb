// Raw samples pass unchanged, and keyed topics get the instance Fast DDS's generated code gives.
#include "raw_endpoints.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "macsim/msg/macsim_msgsPubSubTypes.h"

namespace macsim::topic {
namespace {

using eprosima::fastrtps::rtps::InstanceHandle_t;
using eprosima::fastrtps::rtps::SerializedPayload_t;

template <class PubSub>
void expect_same_instance(typename PubSub::type sample, const std::string& type_name) {
  PubSub generated;
  RawType raw(type_name, wire_type(type_name));
  ASSERT_TRUE(raw.m_isGetKeyDefined) << type_name;
  SerializedPayload_t payload(generated.getSerializedSizeProvider(&sample)());
  ASSERT_TRUE(generated.serialize(&sample, &payload));
  RawSample bytes;
  ASSERT_TRUE(raw.deserialize(&payload, &bytes));
  EXPECT_EQ(bytes.bytes.size(), payload.length);
  SerializedPayload_t again(raw.getSerializedSizeProvider(&bytes)());
  ASSERT_TRUE(raw.serialize(&bytes, &again));
  EXPECT_TRUE(std::equal(bytes.bytes.begin(), bytes.bytes.end(), again.data));
  InstanceHandle_t from_raw, from_generated;
  ASSERT_TRUE(raw.getKey(&bytes, &from_raw, false));
  ASSERT_TRUE(generated.getKey(&sample, &from_generated, false));
  EXPECT_EQ(from_raw, from_generated) << type_name;  // one instance for both kinds of writer
}

TEST(RawType, KeysAreThoseOfTheGeneratedTypes) {
  macsim_msgs::msg::dds_::ObjectState_ object;  // a uint32 key: the bytes themselves
  object.id(42);
  object.object().name("can");
  expect_same_instance<macsim_msgs::msg::dds_::ObjectState_PubSubType>(
      object, "macsim_msgs::msg::dds_::ObjectState_");
  macsim_msgs::msg::dds_::DoorState_ door;  // a string key: its MD5
  door.name("environment_00/door_01");
  expect_same_instance<macsim_msgs::msg::dds_::DoorState_PubSubType>(
      door, "macsim_msgs::msg::dds_::DoorState_");
}

TEST(RawType, UnkeyedAndMalformedSamplesHaveNoKey) {
  RawType odometry("nav_msgs::msg::dds_::Odometry_", wire_type("nav_msgs::msg::dds_::Odometry_"));
  EXPECT_FALSE(odometry.m_isGetKeyDefined);
  RawType unknown("some::Other_", nullptr);
  EXPECT_FALSE(unknown.m_isGetKeyDefined);
  RawType object("macsim_msgs::msg::dds_::ObjectState_",
                 wire_type("macsim_msgs::msg::dds_::ObjectState_"));
  RawSample broken{{0, 1, 0, 0, 1}};
  InstanceHandle_t key;
  EXPECT_FALSE(object.getKey(&broken, &key, false));
  SerializedPayload_t tiny(2);
  tiny.length = 2;
  RawSample out;
  EXPECT_FALSE(object.deserialize(&tiny, &out));
}

}  // namespace
}  // namespace macsim::topic
