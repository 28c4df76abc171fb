// Samples between the wire and YAML, checked against the generated types of the same IDL.
#include "cdr_yaml.h"

#include <gtest/gtest.h>

#include "macsim/dds/dynamic_types.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"

namespace macsim::topic {
namespace {

using Payload = eprosima::fastrtps::rtps::SerializedPayload_t;

template <class PubSub>
std::vector<std::uint8_t> serialize(typename PubSub::type sample) {
  PubSub type;
  Payload payload(type.getSerializedSizeProvider(&sample)());
  EXPECT_TRUE(type.serialize(&sample, &payload));
  return {payload.data, payload.data + payload.length};
}

template <class PubSub>
typename PubSub::type deserialize(const std::vector<std::uint8_t>& bytes) {
  PubSub type;
  Payload payload(static_cast<uint32_t>(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = static_cast<uint32_t>(bytes.size());
  typename PubSub::type sample;
  EXPECT_TRUE(type.deserialize(&payload, &sample));
  return sample;
}

const WireType& type_of(const std::string& name) {
  auto type = wire_type(name);
  if (!type) throw std::runtime_error("no IDL type " + name);
  static std::vector<WireTypePtr> keep;
  keep.push_back(type);
  return *type;
}

nav_msgs::msg::dds_::Odometry_ odometry() {
  nav_msgs::msg::dds_::Odometry_ o;
  o.header().stamp().sec(12);
  o.header().stamp().nanosec(500000000);
  o.header().frame_id("odom");
  o.child_frame_id("base_footprint");
  o.pose().pose().position().x(1.25);
  o.pose().pose().orientation().w(1.0);
  o.pose().covariance()[0] = 0.001;
  o.twist().twist().angular().z(-0.5);
  return o;
}

TEST(CdrYaml, PrintsOdometryAsRos2TopicEchoDoes) {
  const std::string yaml = sample_to_yaml(serialize<nav_msgs::msg::dds_::Odometry_PubSubType>(odometry()),
                                          type_of("nav_msgs::msg::dds_::Odometry_"));
  const std::string expected =
            "header:\n  stamp:\n    sec: 12\n    nanosec: 500000000\n  frame_id: odom\n"
            "child_frame_id: base_footprint\npose:\n  pose:\n    position:\n      x: 1.25\n"
            "      y: 0.0\n      z: 0.0\n    orientation:\n      x: 0.0\n      y: 0.0\n"
            "      z: 0.0\n      w: 1.0\n  covariance:\n  - 0.001\n  - 0.0\n";
  EXPECT_EQ(yaml.substr(0, expected.size()), expected);
  EXPECT_NE(yaml.find("    angular:\n      x: 0.0\n      y: 0.0\n      z: -0.5\n"),
            std::string::npos)
      << yaml;
}

TEST(CdrYaml, PrintsOneFieldAndArraysAsTheirLength) {
  const auto bytes = serialize<nav_msgs::msg::dds_::Odometry_PubSubType>(odometry());
  const auto& type = type_of("nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(sample_to_yaml(bytes, type, {false, "pose.pose.position"}), "x: 1.25\ny: 0.0\nz: 0.0\n");
  EXPECT_EQ(sample_to_yaml(bytes, type, {false, "twist.twist.angular.z"}), "-0.5\n");
  EXPECT_EQ(sample_to_yaml(bytes, type, {false, "pose.covariance.0"}), "0.001\n");
  EXPECT_EQ(sample_to_yaml(bytes, type, {false, "header.frame_id"}), "odom\n");
  const std::string no_arr = sample_to_yaml(bytes, type, {true, ""});
  EXPECT_NE(no_arr.find("  covariance: '<array type: float64[36]>'\n"), std::string::npos) << no_arr;
  try {
    sample_to_yaml(bytes, type, {false, "pose.pose.positio"});
    FAIL() << "a field that does not exist was printed";
  } catch (const SampleError& e) {
    EXPECT_STREQ(e.what(),
                 "no field 'pose.pose.positio' in geometry_msgs/msg/Pose (fields: position, "
                 "orientation)");
  }
  EXPECT_THROW(sample_to_yaml(bytes, type, {false, "pose.covariance.36"}), SampleError);
}

TEST(CdrYaml, ImagesPrintTheirHeaderWithoutTouchingThePixels) {
  sensor_msgs::msg::dds_::Image_ image;
  image.header().frame_id("left_camera");
  image.height(480);
  image.width(640);
  image.encoding("bgr8");
  image.step(1920);
  image.data().assign(640 * 480 * 3, 7);
  const auto bytes = serialize<sensor_msgs::msg::dds_::Image_PubSubType>(image);
  const auto& type = type_of("sensor_msgs::msg::dds_::Image_");
  EXPECT_EQ(sample_to_yaml(bytes, type, {false, "header"}),
            "stamp:\n  sec: 0\n  nanosec: 0\nframe_id: left_camera\n");
  const std::string no_arr = sample_to_yaml(bytes, type, {true, ""});
  EXPECT_NE(no_arr.find("data: '<sequence type: uint8, length: 921600>'"), std::string::npos)
      << no_arr;
  EXPECT_NE(no_arr.find("encoding: bgr8"), std::string::npos) << no_arr;
}

TEST(CdrYaml, UnionsPrintTheCaseTheyHoldAndFillFromIt) {
  macsim_msgs::msg::dds_::SupervisorRequest_ request;
  request.client_id("cli");
  request.sequence_number(7);
  macsim_msgs::msg::dds_::SetPose_ set_pose;
  set_pose.object_id(3);
  set_pose.pose().position().x(1.5);
  request.operation().set_pose(set_pose);
  const auto bytes = serialize<macsim_msgs::msg::dds_::SupervisorRequest_PubSubType>(request);
  const auto& type = type_of("macsim_msgs::msg::dds_::SupervisorRequest_");
  const std::string yaml = sample_to_yaml(bytes, type);
  EXPECT_NE(yaml.find("operation:\n  set_pose:\n    object_id: 3\n    pose:\n"), std::string::npos)
      << yaml;
  // the printed YAML fills the same bytes back
  EXPECT_EQ(sample_from_yaml(YAML::Load(yaml), type), bytes);
  const auto filled = deserialize<macsim_msgs::msg::dds_::SupervisorRequest_PubSubType>(
      sample_from_yaml(YAML::Load("{client_id: x, operation: {find_object: {name: can}}}"), type));
  EXPECT_EQ(filled.client_id(), "x");
  EXPECT_EQ(filled.operation()._d(), macsim_msgs::msg::dds_::OP_FIND_OBJECT);
  EXPECT_EQ(filled.operation().find_object().name(), "can");
}

TEST(CdrYaml, FillsWhatTheYamlNamesAndZeroesTheRest) {
  const auto& type = type_of("nav_msgs::msg::dds_::Odometry_");
  const auto o = deserialize<nav_msgs::msg::dds_::Odometry_PubSubType>(sample_from_yaml(
      YAML::Load("{child_frame_id: base_footprint, pose: {pose: {position: {x: 2.5}}}}"), type));
  EXPECT_EQ(o.child_frame_id(), "base_footprint");
  EXPECT_EQ(o.pose().pose().position().x(), 2.5);
  EXPECT_EQ(o.pose().pose().orientation().w(), 1.0);  // ROS's Quaternion default: identity
  EXPECT_EQ(o.twist().covariance()[35], 0.0);
}

TEST(CdrYaml, RefusesYamlThatDoesNotFitNamingTheField) {
  const auto& twist = type_of("geometry_msgs::msg::dds_::Twist_");
  auto error = [&](const std::string& yaml, const WireType& type) {
    try {
      sample_from_yaml(YAML::Load(yaml), type);
    } catch (const SampleError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error("{linear: {q: 1}}", twist),
            "no field 'linear.q' in geometry_msgs/msg/Vector3 (fields: x, y, z)");
  EXPECT_EQ(error("{linear: {x: abc}}", twist), "field 'linear.x': expected a number, got 'abc'");
  EXPECT_EQ(error("{linear: 3}", twist).rfind("field 'linear': expected a mapping", 0), 0u);
  const auto& image = type_of("sensor_msgs::msg::dds_::Image_");
  EXPECT_EQ(error("{height: -1}", image),
            "field 'height': expected an integer that fits uint32, got '-1'");
  EXPECT_EQ(error("{height: 1e308}", image),
            "field 'height': expected an integer that fits uint32, got '1e308'");
  const auto& odom = type_of("nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(error("{pose: {covariance: [1, 2]}}", odom),
            "field 'pose.covariance': expected a sequence of exactly 36 items, got a sequence");
  const auto& request = type_of("macsim_msgs::msg::dds_::SupervisorRequest_");
  EXPECT_EQ(error("{operation: {fly: {}}}", request).rfind("no case 'operation.fly'", 0), 0u);
}

TEST(CdrYaml, TruncatedOrForeignSamplesAreErrorsNotCrashes) {
  const auto bytes = serialize<nav_msgs::msg::dds_::Odometry_PubSubType>(odometry());
  const auto& type = type_of("nav_msgs::msg::dds_::Odometry_");
  for (std::size_t cut : {0ul, 3ul, 4ul, 10ul, 30ul, bytes.size() - 1}) {
    std::vector<std::uint8_t> shorter(bytes.begin(), bytes.begin() + static_cast<long>(cut));
    EXPECT_THROW(sample_to_yaml(shorter, type), SampleError) << cut;
  }
  auto huge = bytes;  // a frame_id length far beyond the sample
  huge[12] = 0xff;
  huge[13] = 0xff;
  huge[14] = 0xff;
  huge[15] = 0x7f;
  EXPECT_THROW(sample_to_yaml(huge, type), SampleError);
  auto xcdr2 = bytes;
  xcdr2[1] = 0x07;
  EXPECT_THROW(sample_to_yaml(xcdr2, type), SampleError);
}

TEST(CdrYaml, EveryIdlTypeRoundTripsThroughYaml) {
  int structs = 0;
  for (const auto& name : dds::idl_type_names()) {
    auto type = wire_type(name);
    ASSERT_TRUE(type) << name;
    if (type->kind != WireType::Kind::Struct) continue;
    ++structs;
    const auto zero = sample_from_yaml(YAML::Node(), *type);
    const std::string yaml = sample_to_yaml(zero, *type);
    EXPECT_EQ(sample_from_yaml(YAML::Load(yaml), *type), zero) << name << ":\n" << yaml;
  }
  EXPECT_GE(structs, 50);
}

TEST(CdrYaml, TheRangeHasJazzysLayout) {
  const auto& range = type_of("sensor_msgs::msg::dds_::Range_");
  std::vector<std::string> names;
  for (const auto& m : range.members) names.push_back(m.name + ":" + display_name(*m.type));
  EXPECT_EQ(names, (std::vector<std::string>{"header:std_msgs/msg/Header", "radiation_type:uint8",
                                             "field_of_view:float32", "min_range:float32",
                                             "max_range:float32", "range:float32",
                                             "variance:float32"}));
}

}  // namespace
}  // namespace macsim::topic
