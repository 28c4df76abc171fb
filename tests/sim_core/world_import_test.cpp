// The <IMPORT> hierarchy: relative paths, composed transforms, cycles, missing files, textures,
// materials, and the seed's naming conventions (warned about, never a reason to hide objects).
#include <gtest/gtest.h>

#include <fstream>

#include "macsim/images/image_files.h"
#include "macsim/sim_core/log_sink.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

class WorldImport : public ::testing::Test {
 protected:
  std::filesystem::path dir =
      temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::vector<std::string> warnings;

  WorldSpec load(const std::string& file = "world.xml") {
    const ScopedLogSink capture(
        [this](LogLevel, const std::string& w) { warnings.push_back(w); });
    return load_world_file((dir / file).string());
  }

  // Expects loading to fail in `file` at `line` with `fragment` in the message.
  void expect_error(const std::string& file, int line, const std::string& fragment) {
    try {
      load();
      FAIL() << "loaded although it should not";
    } catch (const WorldFileError& e) {
      EXPECT_EQ(std::filesystem::path(e.file()).filename(), file) << e.what();
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
};

TEST_F(WorldImport, NestedImportsComposeTransformsAndResolvePathsRelativeToTheImporter) {
  write_file(dir / "world.xml", R"(<WORLD>
    <IMPORT><ID>env</ID><NAME>a/env.xml</NAME><POS>1,0,0</POS><ROT>0,0,90</ROT></IMPORT></WORLD>)");
  write_file(dir / "a/env.xml", R"(<ENVIRONMENT>
    <IMPORT><ID>inner</ID><NAME>b/inner.xml</NAME><POS>1,0,0</POS></IMPORT></ENVIRONMENT>)");
  write_file(dir / "a/b/inner.xml", R"(<ENVIRONMENT>
    <OBJECT><ID>box</ID><SHAPE>BOX</SHAPE><DIMS>0.1,0.1,0.1</DIMS><POS>0,0,0.5</POS></OBJECT>
    <ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE><POS>0,1,0</POS></ROBOT></ENVIRONMENT>)");
  const WorldSpec spec = load();
  ASSERT_EQ(spec.objects.size(), 1u);
  EXPECT_EQ(spec.objects[0].name, "env/inner/box");
  // env frame: (1,0,0) turned 90 deg; inner at env's +x, i.e. world +y: (1,1,0); box 0.5 up.
  EXPECT_TRUE(spec.objects[0].pose.position.isApprox(Eigen::Vector3d(1, 1, 0.5), 1e-12));
  ASSERT_EQ(spec.robots.size(), 1u);
  EXPECT_TRUE(spec.robots[0].pose.position.isApprox(Eigen::Vector3d(0, 1, 0),
                                                    1e-12));  // inner +y = world -x
  EXPECT_TRUE(warnings.empty());
}

TEST_F(WorldImport, AMissingImportedFileNamesTheImportingFileAndLine) {
  write_file(dir / "world.xml",
             "<WORLD>\n\n<IMPORT><ID>x</ID><NAME>nowhere.xml</NAME></IMPORT></WORLD>");
  expect_error("world.xml", 3, "nowhere.xml");
}

TEST_F(WorldImport, ImportCyclesAreRefused) {
  write_file(dir / "world.xml", "<WORLD><IMPORT><ID>a</ID><NAME>a.xml</NAME></IMPORT></WORLD>");
  write_file(dir / "a.xml",
             "<ENVIRONMENT>\n<IMPORT><ID>b</ID><NAME>b.xml</NAME></IMPORT></ENVIRONMENT>");
  write_file(dir / "b.xml",
             "<ENVIRONMENT>\n\n<IMPORT><ID>a</ID><NAME>a.xml</NAME></IMPORT></ENVIRONMENT>");
  expect_error("b.xml", 3, "import cycle");
}

TEST_F(WorldImport, ErrorsInsideAnImportedFileNameThatFile) {
  write_file(dir / "world.xml", "<WORLD><IMPORT><ID>a</ID><NAME>a.xml</NAME></IMPORT></WORLD>");
  write_file(dir / "a.xml",
             "<ENVIRONMENT>\n<OBJECT><ID>s</ID><SHAPE>SPHERE</SHAPE>\n<RADIUS>-1</RADIUS></"
             "OBJECT></ENVIRONMENT>");
  expect_error("a.xml", 3, "<RADIUS> must be positive");
}

TEST_F(WorldImport, ImportedFilesMustBeEnvironments) {
  write_file(dir / "world.xml", "<WORLD><IMPORT><ID>a</ID><NAME>a.xml</NAME></IMPORT></WORLD>");
  write_file(dir / "a.xml", "<WORLD/>");
  expect_error("a.xml", 1, "<ENVIRONMENT>");
}

TEST_F(WorldImport, TexturesAreCheckedWhenLoading) {
  macsim::images::write_image((dir / "ok.bmp").string(), cv::Mat(64, 64, CV_8UC3, cv::Scalar(1, 2, 3)));
  macsim::images::write_image((dir / "npot.bmp").string(), cv::Mat(48, 48, CV_8UC3, cv::Scalar(1, 2, 3)));
  write_file(dir / "world.xml", R"(<WORLD>
<OBJECT><ID>a</ID><SHAPE>BOX</SHAPE><DIMS>1,1,1</DIMS><TEXTURE>ok.bmp</TEXTURE></OBJECT>
<OBJECT><ID>b</ID><SHAPE>BOX</SHAPE><DIMS>1,1,1</DIMS>
<TEXTURE>npot.bmp</TEXTURE></OBJECT></WORLD>)");
  expect_error("world.xml", 4, "2^n x 2^n");
  write_file(dir / "world.xml", R"(<WORLD>
<OBJECT><ID>a</ID><SHAPE>BOX</SHAPE><DIMS>1,1,1</DIMS><TEXTURE>ok.bmp</TEXTURE></OBJECT></WORLD>)");
  EXPECT_EQ(load().objects[0].components[0].texture, (dir / "ok.bmp").string());
  // A BMP cut short: refused by its header, before the decoder sees it.
  std::ifstream whole(dir / "ok.bmp", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(whole)), {});
  write_file(dir / "cut.bmp", bytes.substr(0, bytes.size() / 2));
  write_file(dir / "world.xml", R"(<WORLD>
<OBJECT><ID>a</ID><SHAPE>BOX</SHAPE><DIMS>1,1,1</DIMS>
<TEXTURE>cut.bmp</TEXTURE></OBJECT></WORLD>)");
  expect_error("world.xml", 3, "truncated BMP");
}

TEST_F(WorldImport, MaterialsGiveFrictionBounceAndDefaultDensity) {
  write_file(dir / "world.xml", R"(<WORLD>
    <MATERIAL><NAME>rubber</NAME><FRICTION>1.2</FRICTION><BOUNCE>0.6</BOUNCE><DENSITY>900</DENSITY></MATERIAL>
    <OBJECT><ID>ball</ID><SHAPE>SPHERE</SHAPE><RADIUS>0.1</RADIUS><POS>0,0,1</POS><MATERIAL>rubber</MATERIAL></OBJECT>
    <OBJECT><ID>stone</ID><SHAPE>SPHERE</SHAPE><RADIUS>0.1</RADIUS><POS>1,0,1</POS></OBJECT></WORLD>)");
  const WorldSpec spec = load();
  EXPECT_DOUBLE_EQ(spec.objects[0].density, 900);
  EXPECT_DOUBLE_EQ(spec.material("rubber")->bounce, 0.6);
  // Physically: the rubber ball bounces back up, the default one does not.
  World world(spec);
  double rubber_peak = 0, stone_peak = 0;
  bool rubber_landed = false, stone_landed = false;
  for (int i = 0; i < 1500; ++i) {
    world.step();
    const double r = world.objects().object_state(*world.objects().find_object("ball")).value.pose.position.z();
    const double s = world.objects().object_state(*world.objects().find_object("stone")).value.pose.position.z();
    rubber_landed |= r < 0.11;
    stone_landed |= s < 0.11;
    if (rubber_landed) rubber_peak = std::max(rubber_peak, r);
    if (stone_landed) stone_peak = std::max(stone_peak, s);
  }
  EXPECT_GT(rubber_peak, 0.25);
  EXPECT_LT(stone_peak, 0.12);
}

TEST_F(WorldImport, UnknownOrConflictingMaterialsAreErrors) {
  write_file(dir / "world.xml",
             "<WORLD>\n<OBJECT><ID>a</ID><SHAPE>BOX</SHAPE><DIMS>1,1,1</"
             "DIMS>\n<MATERIAL>unobtainium</MATERIAL></OBJECT></WORLD>");
  expect_error("world.xml", 3, "unknown material 'unobtainium'");
  write_file(dir / "world.xml", R"(<WORLD>
<MATERIAL><NAME>m</NAME><FRICTION>1</FRICTION></MATERIAL>
<MATERIAL><NAME>m</NAME><FRICTION>2</FRICTION></MATERIAL></WORLD>)");
  expect_error("world.xml", 3, "defined twice");
}

TEST_F(WorldImport, CompositesWallsAndRampsAreRead) {
  write_file(dir / "world.xml", R"(<WORLD>
    <OBJECT><ID>can</ID><USER_APPS><MAGNETIZABLE>true</MAGNETIZABLE></USER_APPS><MASS>0.1</MASS>
      <COMPONENT><SHAPE>CYLINDER</SHAPE><RADIUS>0.03</RADIUS><HEIGHT>0.1</HEIGHT><POS>0,0,0.05</POS></COMPONENT>
      <COMPONENT><SHAPE>SPHERE</SHAPE><RADIUS>0.02</RADIUS><POS>0,0,0.1</POS></COMPONENT></OBJECT>
    <WALL><ID>w</ID><POS>0,2,0</POS><LENGTH>4</LENGTH><HEIGHT>0.5</HEIGHT></WALL>
    <RAMP><ID>r</ID><POS>1,0,0</POS><WIDTH>1</WIDTH><DEPTH>0.5</DEPTH><ANGLE>10</ANGLE></RAMP></WORLD>)");
  const WorldSpec spec = load();
  ASSERT_EQ(spec.objects.size(), 3u);
  EXPECT_EQ(spec.objects[0].components.size(), 2u);
  EXPECT_TRUE(spec.objects[0].magnetizable);
  EXPECT_NEAR(spec.objects[0].mass(), 0.1, 1e-12);
  EXPECT_EQ(spec.objects[1].kind, ObjectKind::Wall);
  EXPECT_FALSE(spec.objects[1].portable);
  EXPECT_EQ(spec.objects[1].components[0].size, Eigen::Vector3d(4, 0.1, 0.5));
  ASSERT_TRUE(spec.objects[2].ramp.has_value());
  EXPECT_NEAR(spec.objects[2].ramp->depth(), 0.5, 1e-12);  // given as depth, height derived
  EXPECT_NEAR(spec.objects[2].ramp->height, 0.5 * std::tan(10 * M_PI / 180), 1e-12);
}

TEST_F(WorldImport, RampsNeedExactlyOneOfHeightAndDepth) {
  write_file(dir / "world.xml",
             "<WORLD>\n<RAMP><ID>r</ID><WIDTH>1</WIDTH><HEIGHT>0.1</HEIGHT><DEPTH>1</"
             "DEPTH><ANGLE>10</ANGLE></RAMP></WORLD>");
  expect_error("world.xml", 2, "one of <HEIGHT> or <DEPTH>");
}

TEST_F(WorldImport, BrokenDoorConventionsAreWarnedAboutAndEverythingStaysReachable) {
  write_file(dir / "door.xml", R"(<ENVIRONMENT>
    <OBJECT><ID>frame</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE><DIMS>0.1,1,0.1</DIMS><POS>0,0,1</POS></OBJECT>
    <OBJECT><ID>leaf</ID><SHAPE>BOX</SHAPE><DIMS>0.05,0.8,0.6</DIMS><POS>0,0,0.31</POS></OBJECT>
    <JOINT><ID>j</ID><TYPE>SLIDER</TYPE><BODY1>leaf</BODY1><BODY2>frame</BODY2><AXIS>0,1,0</AXIS><HI>0.8</HI>
      <VELOCITY>0.3</VELOCITY><MAX_FORCE>20</MAX_FORCE></JOINT></ENVIRONMENT>)");
  write_file(
      dir / "door_switch.xml",
      "<ENVIRONMENT><IMPORT><ID>door_component</ID><NAME>door.xml</NAME></IMPORT></ENVIRONMENT>");
  write_file(dir / "doors.xml", R"(<ENVIRONMENT>
    <IMPORT><ID>front_door</ID><NAME>door_switch.xml</NAME></IMPORT></ENVIRONMENT>)");
  write_file(dir / "world.xml", R"(<WORLD>
    <IMPORT><ID>doors</ID><NAME>doors.xml</NAME></IMPORT>
    <IMPORT><ID>my_environment</ID><NAME>door_switch.xml</NAME><POS>3,0,0</POS></IMPORT></WORLD>)");
  const WorldSpec spec = load();
  EXPECT_EQ(spec.doors.size(), 2u);  // both work as doors
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("door_%02d"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("not inside a <ID>doors</ID> container"), std::string::npos)
      << warnings[1];
  World world(spec);
  EXPECT_TRUE(world.objects().find_object("doors/front_door/door_component/leaf").has_value());
  EXPECT_TRUE(world.objects().find_object("my_environment/door_component/leaf").has_value());
  EXPECT_EQ(world.doors().find_door("my_environment"), 1);
}

TEST_F(WorldImport, TheShippedWorldsLoadWithoutWarnings) {
  for (const char* file : {"DemoWorld_v1.xml", "small_room.xml", "liftability.xml", "ramps.xml",
                           "figure12_fixed_obstacles.xml", "figure13_steps_joist.xml",
                           "figure14_cylinder_orientations.xml", "stackability.xml",
                           "goals/demonstrator.xml", "goals/door_open.xml", "goals/stiff_switch.xml", "goals/push_to_switch.xml", "behaviour_trials.xml"}) {
    std::vector<std::string> w;
    const ScopedLogSink capture([&](LogLevel, const std::string& m) { w.push_back(m); });
    const WorldSpec spec = load_world_file(source(std::string("worlds/") + file));
    EXPECT_TRUE(w.empty()) << file << ": " << w.front();
    EXPECT_FALSE(spec.objects.empty()) << file;
    World world(spec);
    run_for(world, 0.5);
    for (const auto& e : world.take_events()) {
      EXPECT_NE(e.type, WorldEvent::Type::Instability) << file << ": " << e.subject;
    }
  }
}

}  // namespace
}  // namespace macsim::test
