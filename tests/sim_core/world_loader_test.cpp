// World files: what loads, and what is refused with the file and line named.
#include "macsim/sim_core/world_loader.h"

#include <gtest/gtest.h>

#include <fstream>

#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/world.h"
#include "support/child_process.h"

namespace macsim {
namespace {

// Expects loading `xml` to fail at `line` with a message containing `fragment`.
void expect_error(const std::string& xml, int line, const std::string& fragment) {
  try {
    load_world_string(xml, "inline.xml");
    FAIL() << "loaded although it should not: " << xml;
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.file(), "inline.xml");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("inline.xml:" + std::to_string(line) + ":", 0), 0u)
        << e.what();
  }
}

TEST(WorldLoader, LoadsTheSmallRoom) {
  const WorldSpec spec = load_world_file(test::source("worlds/small_room.xml"));
  EXPECT_EQ(spec.name, "small_room");
  ASSERT_EQ(spec.robots.size(), 1u);
  EXPECT_EQ(spec.robots[0].name, "kurt");
  EXPECT_EQ(spec.robots[0].type, "kurt3d");
  ASSERT_EQ(spec.objects.size(), 4u);
  EXPECT_FALSE(spec.objects[0].portable);
  EXPECT_EQ(spec.objects[2].components.at(0).shape, Shape::Cylinder);
  EXPECT_DOUBLE_EQ(spec.objects[2].mass(), 0.04);
  EXPECT_DOUBLE_EQ(spec.physics.step, 0.001);
}

TEST(WorldLoader, ReadsPosesInMetresAndRotationsInDegrees) {
  const WorldSpec spec = load_world_string(R"(<WORLD>
    <ROBOT><ID>k</ID><TYPE>kurt3d</TYPE><POS>1,2,0</POS><ROT>0,0,90</ROT></ROBOT></WORLD>)",
                                           "w.xml");
  const Pose& p = spec.robots[0].pose;
  EXPECT_EQ(p.position, Eigen::Vector3d(1, 2, 0));
  const Eigen::Vector3d x = p.orientation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x.y(), 1.0, 1e-12);  // yaw 90 degrees turns +x onto +y
}

TEST(WorldLoader, MalformedXmlNamesFileAndLine) {
  // tinyxml2 names the line where the element that is not closed properly was opened.
  expect_error("<WORLD>\n<ROBOT>\n<ID>kurt</ID>\n</ROBT>\n</WORLD>", 2,
               "malformed XML: element not closed by its end tag <ROBOT>");
  expect_error("<WORLD>\n<ROBOT>\n<ID>kurt</ID>\n<POS 1,2,3</POS></ROBOT>\n</WORLD>", 4,
               "malformed XML");
}

TEST(WorldLoader, MalformedFileOnDiskNamesThePath) {
  const std::string path = ::testing::TempDir() + "broken_world.xml";
  std::ofstream(path) << "<WORLD>\n  <OBJECT>\n    <ID>a</ID>\n  <OBJECT>\n</WORLD>\n";
  try {
    load_world_file(path);
    FAIL() << "loaded a malformed file";
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_GT(e.line(), 0);
    EXPECT_NE(std::string(e.what()).find(path + ":"), std::string::npos);
  }
}

TEST(WorldLoader, MissingFileIsAnError) {
  try {
    load_world_file("no/such/world.xml");
    FAIL();
  } catch (const WorldFileError& e) {
    EXPECT_NE(std::string(e.what()).find("no/such/world.xml"), std::string::npos);
  }
}

TEST(WorldLoader, RootMustBeWorld) { expect_error("<ROBOT/>", 1, "<WORLD>"); }

TEST(WorldLoader, BadNumberNamesTheElementsLine) {
  expect_error("<WORLD>\n<PHYSICS>\n<STEP>fast</STEP>\n</PHYSICS>\n</WORLD>", 3, "<STEP>");
  expect_error("<WORLD>\n<ROBOT><ID>k</ID><TYPE>kurt3d</TYPE>\n<POS>1,2</POS></ROBOT></WORLD>", 3,
               "expects 3 numbers");
  expect_error("<WORLD>\n<PHYSICS><STEP>nan</STEP></PHYSICS></WORLD>", 2, "finite");
}

TEST(WorldLoader, NonPositiveSizesAreRefused) {
  expect_error(R"(<WORLD>
<OBJECT><ID>b</ID><SHAPE>BOX</SHAPE>
<DIMS>0.1,-0.2,0.1</DIMS></OBJECT></WORLD>)",
               3, "positive");
  expect_error(R"(<WORLD>
<OBJECT><ID>s</ID><SHAPE>SPHERE</SHAPE><RADIUS>0</RADIUS></OBJECT></WORLD>)",
               2, "positive");
  expect_error(R"(<WORLD><PHYSICS>
<STEP>-0.001</STEP></PHYSICS></WORLD>)",
               2, "positive");
}

TEST(WorldLoader, MissingRequiredElementsAreNamed) {
  expect_error("<WORLD>\n<OBJECT><SHAPE>BOX</SHAPE></OBJECT></WORLD>", 2, "<ID>");
  expect_error("<WORLD>\n<OBJECT><ID>c</ID><SHAPE>CYLINDER</SHAPE><RADIUS>1</RADIUS></OBJECT>"
               "</WORLD>",
               2, "<HEIGHT>");
  expect_error("<WORLD>\n<ROBOT><ID>k</ID></ROBOT></WORLD>", 2, "<TYPE>");
  expect_error("<WORLD>\n<OBJECT><ID>c</ID><SHAPE>CONE</SHAPE></OBJECT></WORLD>", 2, "CONE");
}

TEST(WorldLoader, DuplicateIdsAreRefused) {
  expect_error(R"(<WORLD>
<ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT>
<ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT></WORLD>)",
               3, "duplicate id 'kurt'");
}

TEST(WorldLoader, RobotIdMustBeATopicName) {
  expect_error("<WORLD>\n<ROBOT><ID>my robot</ID><TYPE>kurt3d</TYPE></ROBOT></WORLD>", 2,
               "topic name");
}

TEST(WorldLoader, UnknownElementsAreWarnedAboutWithTheirLine) {
  std::vector<std::string> warnings;
  std::vector<LogLevel> levels;
  const ScopedLogSink capture([&](LogLevel level, const std::string& w) {
    levels.push_back(level);
    warnings.push_back(w);
  });
  const WorldSpec spec = load_world_string("<WORLD>\n\n<TELEPORTER/>\n</WORLD>", "w.xml");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(levels[0], LogLevel::Warning);
  EXPECT_NE(warnings[0].find("w.xml:3:"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("TELEPORTER"), std::string::npos);
  EXPECT_TRUE(spec.objects.empty());
}

TEST(World, UnknownRobotTypeNamesTheRobotsLine) {
  try {
    load_world_string("<WORLD>\n\n<ROBOT><ID>r2</ID><TYPE>r2d2</TYPE></ROBOT></WORLD>", "w.xml");
    FAIL();
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("r2d2"), std::string::npos);
  }
}

}  // namespace
}  // namespace macsim
