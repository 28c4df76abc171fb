// The KURT3D's one description: its numbers agree with each other (the axles' height and the
// wheels' radius give base_link's height, the sensors sit on the body) and its text, which the
// robot node publishes, carries every number once and reads back to the same values.
#include "macsim/robot/kurt3d_description.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>
#include <vector>

namespace macsim::test {
namespace {

namespace kurt3d = robot::kurt3d;

/// The text's `name value...` lines, by name (range_sensor lines by their frame).
std::map<std::string, std::vector<std::string>> lines_of(const std::string& text) {
  std::map<std::string, std::vector<std::string>> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string name, word;
    words >> name;
    std::vector<std::string> values;
    while (words >> word) values.push_back(word);
    if (name == "range_sensor" && !values.empty()) {
      name += " " + values.front();
      values.erase(values.begin());
    }
    EXPECT_FALSE(lines.count(name)) << "twice: " << name;
    lines[name] = values;
  }
  return lines;
}

TEST(Kurt3dDescription, ItsNumbersAgreeWithEachOther) {
  EXPECT_NEAR(kurt3d::kWheelRadius * 2 * M_PI, kurt3d::kWheelPerimeter, 1e-12);
  EXPECT_NEAR(kurt3d::kBaseHeight, 0.107 + 0.379 / (2 * M_PI), 1e-12);
  EXPECT_GT(kurt3d::kHalfWidth, kurt3d::kBaseSize[1] / 2);  // the wheels stand out
  EXPECT_GE(kurt3d::kFront, kurt3d::kBaseSize[0] / 2);
  EXPECT_LT(kurt3d::kLiftMin, 0.0);
  EXPECT_GT(kurt3d::kLiftMax, 0.0);
  EXPECT_NEAR(kurt3d::kMagnetBelowTip - kurt3d::kMagnetHeight, 0.02, 1e-12);
  std::set<std::string> frames;
  for (const auto& s : kurt3d::kRangeSensors) {
    frames.insert(s.frame);
    // On the body's edge, facing out of it.
    EXPECT_LE(std::abs(s.x), kurt3d::kFront) << s.frame;
    EXPECT_LE(std::abs(s.y), kurt3d::kHalfWidth) << s.frame;
    const double facing = s.x * std::cos(s.yaw) + s.y * std::sin(s.yaw);
    EXPECT_GT(facing, 0.1) << s.frame;
    EXPECT_LT(s.min_range, s.max_range) << s.frame;
    EXPECT_EQ(s.sonar, std::string(s.frame).rfind("ultrasound", 0) == 0) << s.frame;
  }
  EXPECT_EQ(frames.size(), 8u);
}

TEST(Kurt3dDescription, TheTextCarriesEveryNumberOnceAndReadsBack) {
  const auto lines = lines_of(kurt3d::description_text());
  ASSERT_TRUE(lines.count("robot"));
  EXPECT_EQ(lines.at("robot"), std::vector<std::string>{"kurt3d"});
  auto number = [&](const std::string& name, std::size_t i = 0) {
    EXPECT_TRUE(lines.count(name)) << name;
    return lines.count(name) ? std::stod(lines.at(name).at(i)) : NAN;
  };
  EXPECT_NEAR(number("base_height"), kurt3d::kBaseHeight, 1e-9);
  EXPECT_NEAR(number("wheel_radius"), kurt3d::kWheelRadius, 1e-9);
  EXPECT_EQ(number("ticks_per_turn"), kurt3d::kTicksPerTurn);
  EXPECT_EQ(number("base_size", 2), kurt3d::kBaseSize[2]);
  EXPECT_EQ(number("left_camera", 2), kurt3d::kLeftCamera[2]);
  EXPECT_NEAR(number("camera_pitch"), kurt3d::kCameraPitch, 1e-9);
  EXPECT_EQ(number("rotating_laser", 2), kurt3d::kRotatingLaser[2]);
  EXPECT_EQ(number("boom_length"), kurt3d::kBoomLength);
  EXPECT_EQ(number("magnet_below_tip"), kurt3d::kMagnetBelowTip);
  for (const auto& s : kurt3d::kRangeSensors) {
    const std::string name = std::string("range_sensor ") + s.frame;
    ASSERT_TRUE(lines.count(name)) << name;
    const auto& v = lines.at(name);
    ASSERT_EQ(v.size(), 7u) << name;
    EXPECT_EQ(std::stod(v[0]), s.x);
    EXPECT_EQ(std::stod(v[1]), s.y);
    EXPECT_NEAR(std::stod(v[2]), s.yaw, 1e-9);
    EXPECT_EQ(v[3], s.sonar ? "1" : "0");
    EXPECT_EQ(std::stod(v[5]), s.max_range);
  }
}

}  // namespace
}  // namespace macsim::test
