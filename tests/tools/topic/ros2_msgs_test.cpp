// The ROS 2 interface packages in ros2_msgs/ say what the IDL says, field for field, and miss
// no IDL type that .msg can express.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "macsim/dds/dynamic_types.h"
#include "support/child_process.h"
#include "wire_type.h"

namespace macsim::topic {
namespace {

/// The "type name" lines of a .msg file: comments, blank lines and constants left out.
std::string fields_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    std::string type, name;
    if (!(words >> type >> name)) continue;
    if (name.find('=') != std::string::npos) continue;  // a constant: "int32 NAME=1"
    out += type + " " + name + "\n";
  }
  return out;
}

TEST(Ros2Msgs, EveryMsgFileMatchesItsIdlTypeAndNoneIsMissing) {
  int checked = 0;
  for (const std::string package : {"kurt_msgs", "macsim_msgs"}) {
    const std::filesystem::path dir = test::source("ros2_msgs/" + package + "/msg");
    std::set<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      files.insert(entry.path().stem().string());
    }
    for (const auto& dds_name : dds::idl_type_names()) {
      if (dds_name.rfind(package + "::msg::dds_::", 0) != 0) continue;
      const auto type = wire_type(dds_name);
      ASSERT_TRUE(type) << dds_name;
      const std::string definition = ros2_msg_definition(*type);
      if (type->kind != WireType::Kind::Struct || definition.empty()) continue;  // unions
      const std::string ros = dds::ros_type_name(dds_name);
      const std::string name = ros.substr(ros.rfind('/') + 1);
      ASSERT_TRUE(files.count(name)) << "no ros2_msgs/" << package << "/msg/" << name << ".msg";
      EXPECT_EQ(fields_of(dir / (name + ".msg")), definition) << name;
      files.erase(name);
      ++checked;
    }
    EXPECT_TRUE(files.empty()) << package
                               << " has .msg files the IDL does not define: " << *files.begin();
  }
  EXPECT_GE(checked, 40);
}

TEST(Ros2Msgs, DefinitionsNameOtherPackagesAndCarryTheirDependenciesForBags) {
  const auto list = wire_type("macsim_msgs::msg::dds_::ObjectList_");
  ASSERT_TRUE(list);
  EXPECT_EQ(ros2_msg_definition(*list), "std_msgs/Header header\nObject[] objects\n");
  const std::string full = ros2_msg_with_dependencies(*list);
  EXPECT_NE(full.find(std::string(80, '=') + "\nMSG: std_msgs/Header\n"), std::string::npos)
      << full;
  EXPECT_NE(full.find("MSG: macsim_msgs/Object\n"), std::string::npos) << full;
  EXPECT_NE(full.find("MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"),
            std::string::npos)
      << full;
  const auto request = wire_type("macsim_msgs::msg::dds_::SupervisorRequest_");
  ASSERT_TRUE(request);
  EXPECT_EQ(ros2_msg_definition(*request), "");  // a union: .msg cannot say it
  const auto odom = wire_type("nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(ros2_msg_definition(*odom),
            "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance "
            "pose\ngeometry_msgs/TwistWithCovariance twist\n");
}

}  // namespace
}  // namespace macsim::topic
