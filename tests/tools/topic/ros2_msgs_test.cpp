// The ROS 2 interface packages the build writes into build/ros2_msgs/ (from ros2_msgs/ and the
// IDL, by macsim_topic: tools/topic/CMakeLists.txt) say what the IDL says, field for field, miss
// no IDL type that .msg can express, and are .msg files a ROS 2 build reads: every line a field
// of a primitive type or of a message type that exists.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "macsim/dds/dynamic_types.h"
#include "support/child_process.h"
#include "wire_type.h"

namespace macsim::topic {
namespace {

/// Where the build wrote the packages.
const std::filesystem::path kPackages{macsim::test::build_path("ros2_msgs")};
const std::vector<std::string> kOurPackages{"kurt_msgs", "macsim_msgs"};

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
  for (const std::string& package : kOurPackages) {
    const std::filesystem::path dir = kPackages / package / "msg";
    ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir;
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
      ASSERT_TRUE(files.count(name)) << "no " << (dir / (name + ".msg"));
      EXPECT_EQ(fields_of(dir / (name + ".msg")), definition) << name;
      files.erase(name);
      ++checked;
    }
    EXPECT_TRUE(files.empty()) << package
                               << " has .msg files the IDL does not define: " << *files.begin();
  }
  EXPECT_GE(checked, 40);
}

TEST(Ros2Msgs, EveryGeneratedFileIsAMsgOfKnownTypesInAPackage) {
  static const std::set<std::string> primitives{"bool",   "byte",  "char",   "float32", "float64",
                                                "int8",   "uint8", "int16",  "uint16",  "int32",
                                                "uint32", "int64", "uint64", "string",  "wstring"};
  // The packages a definition may name besides ours (their package.xml depends on them).
  static const std::set<std::string> others{"builtin_interfaces", "std_msgs", "geometry_msgs"};
  const std::regex field(
      R"(([A-Za-z0-9_]+/)?([A-Za-z][A-Za-z0-9_]*)(\[(<=)?[0-9]*\])? ([a-z][a-z0-9_]*))");
  for (const std::string& package : kOurPackages) {
    EXPECT_TRUE(std::filesystem::exists(kPackages / package / "package.xml")) << package;
    EXPECT_TRUE(std::filesystem::exists(kPackages / package / "CMakeLists.txt")) << package;
    for (const auto& entry : std::filesystem::directory_iterator(kPackages / package / "msg")) {
      const std::string name = entry.path().stem().string();
      EXPECT_EQ(entry.path().extension(), ".msg") << entry.path();
      EXPECT_TRUE(std::regex_match(name, std::regex("[A-Z][A-Za-z0-9]*"))) << name;
      std::ifstream in(entry.path());
      int fields = 0;
      for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::smatch m;
        ASSERT_TRUE(std::regex_match(line, m, field)) << name << ": '" << line << "'";
        const std::string type_package =
            m[1].matched ? m[1].str().substr(0, m[1].length() - 1) : std::string();
        const std::string type = m[2];
        if (type_package.empty() && primitives.count(type)) {
          ++fields;
          continue;
        }
        const std::string owner = type_package.empty() ? package : type_package;
        if (others.count(owner)) {
          ++fields;
          continue;
        }
        EXPECT_TRUE(std::filesystem::exists(kPackages / owner / "msg" / (type + ".msg")))
            << name << " names " << owner << "/" << type << ", which is no generated .msg";
        ++fields;
      }
      EXPECT_GT(fields, 0) << name;
    }
  }
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
