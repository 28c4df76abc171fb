// kurt_demo's eyes on real renderings: a KURT3D's stereo pair rendered offscreen from a world
// with cans, boxes, switches (raised, and flush with the floor) and look-alikes; each is found where
// it stands (in base_link, within a few centimetres), a box on a flush plate is told from one in
// front of it, the rest is not taken for them.
#include "macsim/affordances/vision.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "macsim/render/camera_modes.h"
#include "macsim/render/renderer.h"
#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/scene.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

/// A can as the demonstrator's: a cylinder of colour `rgb` and a grey bubble top.
std::string can(const std::string& id, double x, double y, const std::string& rgb) {
  return "<OBJECT><ID>" + id + "</ID><POS>" + std::to_string(x) + "," + std::to_string(y) +
         ",0</POS><USER_DATA>can</USER_DATA>"
         "<COMPONENT><SHAPE>CYLINDER</SHAPE><RADIUS>0.033</RADIUS><HEIGHT>0.115</HEIGHT>"
         "<POS>0,0,0.0575</POS><COLOR>" + rgb + "</COLOR></COMPONENT>"
         "<COMPONENT><SHAPE>SPHERE</SHAPE><RADIUS>0.02</RADIUS><POS>0,0,0.115</POS>"
         "<COLOR>0.8,0.8,0.8</COLOR></COMPONENT></OBJECT>";
}

/// The robot's stereo pair of `world` as its cameras publish it (320x240, 45 degrees).
client::StereoFrame stereo(const World& world) {
  const Scene scene = capture_scene(world);
  render::CameraIntrinsics in;
  in.width = 320;
  in.height = 240;
  render::OffscreenRenderer renderer(in.width, in.height);
  client::StereoFrame frame;
  frame.left = renderer.render(scene, render::camera_pose(render::CameraMode::LeftCamera, scene), in);
  frame.right = renderer.render(scene, render::camera_pose(render::CameraMode::RightCamera, scene), in);
  frame.focal = in.focal();
  frame.cx = in.width / 2.0;
  frame.cy = in.height / 2.0;
  frame.baseline = world.robots().front()->cameras()->baseline();
  return frame;
}

const macsim::affordances::Sighting* nearest(const std::vector<macsim::affordances::Sighting>& seen,
                                   macsim::affordances::Kind kind, double x, double y) {
  const macsim::affordances::Sighting* best = nullptr;
  for (const auto& s : seen) {
    if (s.kind == kind && (!best || std::hypot(s.x - x, s.y - y) < std::hypot(best->x - x, best->y - y)))
      best = &s;
  }
  return best;
}

namespace af = macsim::affordances;

/// The push-to-switch family's plate at (x, y): a dark rim round a yellow top, 5 mm over the floor.
std::string flush_plate(double x, double y, double yaw_degrees = 0) {
  return "<OBJECT><ID>plate</ID><TYPE>FIXED</TYPE><POS>" + std::to_string(x) + "," + std::to_string(y) +
         ",0</POS><ROT>0,0," + std::to_string(yaw_degrees) + "</ROT><COMPONENT><SHAPE>BOX</SHAPE><DIMS>0.5,0.5,0.002</DIMS><POS>0,0,0.003</POS>"
         "<COLOR>0.2,0.2,0.2</COLOR></COMPONENT><COMPONENT><SHAPE>BOX</SHAPE><DIMS>0.4,0.4,0.001</DIMS>"
         "<POS>0,0,0.0045</POS><COLOR>0.95,0.8,0.1</COLOR></COMPONENT></OBJECT>";
}

/// What a KURT3D at the origin facing +x, its crane folded aside as kurt_demo carries it, sees
/// of `objects` (world XML).
struct Looked {
  explicit Looked(const std::string& objects)
      : world(load_world_string("<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT>" + objects + "</WORLD>",
                                "vision.xml")) {
    KurtRobot& kurt = *world.robot_as<KurtRobot>("kurt");
    kurt.command_crane({M_PI / 2, 0.6, 0.0});
    run_for(world, 2.5);
    base = kurt.base_link_pose();
    frame = stereo(world);
    seen = af::find_objects(frame, af::KurtGeometry{});
  }
  /// A point of the floor in base_link.
  Eigen::Vector3d in_base(double x, double y) const {
    return base.orientation.inverse() * (Eigen::Vector3d(x, y, 0) - base.position);
  }
  int count(af::Kind kind) const {
    return static_cast<int>(std::count_if(seen.begin(), seen.end(), [&](const af::Sighting& s) { return s.kind == kind; }));
  }
  World world;
  Pose base;
  client::StereoFrame frame;
  std::vector<af::Sighting> seen;
};

TEST(KurtDemoVision, FindsCansAndTheSwitchWhereTheyStand) {
  // base_link is the world shifted up.
  const Looked looked(can("red", 1.3, 0.35, "0.85,0.1,0.1") + can("blue", 2.1, -0.5, "0.1,0.2,0.85") +
                      can("green", 1.0, -0.2, "0.1,0.75,0.2") +
                      // a switch: a dark base and a flat yellow platform
                      "<OBJECT><ID>base</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE><DIMS>0.3,0.3,0.04</DIMS>"
                      "<POS>1.8,0.5,0.02</POS><COLOR>0.25,0.25,0.25</COLOR></OBJECT>"
                      "<OBJECT><ID>platform</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE><DIMS>0.24,0.24,0.008</DIMS>"
                      "<POS>1.8,0.5,0.066</POS><COLOR>0.95,0.8,0.1</COLOR></OBJECT>"
                      // look-alikes: a red cube (a can's colour, not its shape), a yellow box on the floor
                      "<OBJECT><ID>cube</ID><SHAPE>BOX</SHAPE><DIMS>0.1,0.1,0.1</DIMS><POS>1.5,-0.6,0.05</POS>"
                      "<COLOR>0.9,0.15,0.1</COLOR></OBJECT>"
                      "<OBJECT><ID>yellow_box</ID><SHAPE>BOX</SHAPE><DIMS>0.2,0.2,0.12</DIMS>"
                      "<POS>2.4,0.9,0.06</POS><COLOR>0.95,0.85,0.1</COLOR></OBJECT>");
  const auto& seen = looked.seen;
  EXPECT_EQ(looked.count(af::Kind::Can), 3);     // not the cube
  EXPECT_EQ(looked.count(af::Kind::Switch), 1);  // not the yellow box, which stands on the light floor
  EXPECT_EQ(looked.count(af::Kind::Box), 0);     // the cube is too small for a box to push
  const struct {
    const char* colour;
    double x, y;
  } expected[] = {{"red", 1.3, 0.35}, {"blue", 2.1, -0.5}, {"green", 1.0, -0.2}};
  for (const auto& e : expected) {
    const Eigen::Vector3d truth = looked.in_base(e.x, e.y);
    const auto* s = nearest(seen, macsim::affordances::Kind::Can, truth.x(), truth.y());
    ASSERT_NE(s, nullptr) << e.colour;
    EXPECT_EQ(s->colour, e.colour);
    // Stereo at 320x240 with a 0.12 m baseline: a few centimetres, growing with the range.
    EXPECT_NEAR(s->x, truth.x(), 0.02 + 0.02 * truth.x()) << e.colour;
    EXPECT_NEAR(s->y, truth.y(), 0.03) << e.colour;
    EXPECT_NEAR(s->width, 0.066, 0.03) << e.colour;
  }
  const Eigen::Vector3d platform = looked.in_base(1.8, 0.5);
  const auto* sw = nearest(seen, macsim::affordances::Kind::Switch, platform.x(), platform.y());
  ASSERT_NE(sw, nullptr);
  EXPECT_NEAR(sw->x, platform.x(), 0.08);
  EXPECT_NEAR(sw->y, platform.y(), 0.05);
  EXPECT_LT(sw->width, macsim::affordances::kFlushPlateWidth);  // raised: not flush
}

TEST(KurtDemoVision, FindsABoxToPushAndASwitchPlateFlushWithTheFloor) {
  const Looked looked(
      "<OBJECT><ID>box</ID><SHAPE>BOX</SHAPE><DIMS>0.2,0.2,0.2</DIMS><POS>1.6,0.4,0.1</POS><ROT>0,0,20</ROT>"
      "<COLOR>0.1,0.75,0.2</COLOR></OBJECT>" +
      flush_plate(2.2, -0.4));
  const auto& seen = looked.seen;
  EXPECT_EQ(looked.count(af::Kind::Can), 0);
  EXPECT_EQ(looked.count(af::Kind::Box), 1);
  EXPECT_EQ(looked.count(af::Kind::Switch), 1);
  const Eigen::Vector3d box = looked.in_base(1.6, 0.4);
  const auto* b = nearest(seen, af::Kind::Box, box.x(), box.y());
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->colour, "green");
  EXPECT_NEAR(b->x, box.x(), 0.1);  // its middle, not the face the cameras see
  EXPECT_NEAR(b->y, box.y(), 0.05);
  const Eigen::Vector3d plate = looked.in_base(2.2, -0.4);
  const auto* sw = nearest(seen, macsim::affordances::Kind::Switch, plate.x(), plate.y());
  ASSERT_NE(sw, nullptr);
  EXPECT_NEAR(sw->x, plate.x(), 0.12);
  EXPECT_NEAR(sw->y, plate.y(), 0.06);
  EXPECT_GT(sw->width, macsim::affordances::kFlushPlateWidth);
  EXPECT_FALSE(b->on_plate);  // it stands on the floor
}

TEST(KurtDemoVision, TwoBoxesSideBySideAreTwoBoxes) {
  // Two blue boxes touching, across the view 1.8 m ahead: one blob wider than any one box.
  const Looked looked(
      "<OBJECT><ID>box_a</ID><SHAPE>BOX</SHAPE><DIMS>0.2,0.2,0.2</DIMS><POS>1.8,0.1,0.1</POS>"
      "<COLOR>0.1,0.2,0.85</COLOR></OBJECT>"
      "<OBJECT><ID>box_b</ID><SHAPE>BOX</SHAPE><DIMS>0.2,0.2,0.2</DIMS><POS>1.8,-0.1,0.1</POS>"
      "<COLOR>0.1,0.2,0.85</COLOR></OBJECT>");
  ASSERT_EQ(looked.count(af::Kind::Box), 2);
  for (const double y : {0.1, -0.1}) {
    const Eigen::Vector3d box = looked.in_base(1.8, y);
    const auto* b = nearest(looked.seen, af::Kind::Box, box.x(), box.y());
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->colour, "blue");
    EXPECT_NEAR(b->x, box.x(), 0.1) << y;
    EXPECT_NEAR(b->y, box.y(), 0.06) << y;
  }
}

TEST(KurtDemoVision, ABoxStandingOnAFlushPlateShowsThePlateInFrontOfItsFoot) {
  // The same plate; the box on it, then 0.3 m short of it (its foot on the floor in front).
  for (const double short_of : {0.0, 0.3}) {
    const Looked looked("<OBJECT><ID>box</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE><DIMS>0.2,0.2,0.2</DIMS><POS>" +
                        std::to_string(2.0 - short_of) + ",0,0.105</POS><COLOR>0.85,0.1,0.1</COLOR></OBJECT>" +
                        flush_plate(2.0, 0.0));
    const auto& seen = looked.seen;
    const auto box = std::find_if(seen.begin(), seen.end(), [](const auto& s) { return s.kind == af::Kind::Box; });
    ASSERT_NE(box, seen.end()) << short_of;
    EXPECT_EQ(box->on_plate, short_of == 0.0) << short_of;
  }
}

TEST(KurtDemoVision, AFlushPlateIsJudgedFromItsOutlineWithABoxHidingItsMiddle) {
  // Square to the view and turned 25 degrees, alone and with a box on its near half (hiding the
  // turned one's far corner too): its sides put its middle where it is, within a few centimetres.
  for (const double yaw : {0.0, 25.0}) {
    for (const bool box : {false, true}) {
      const Looked looked((box ? std::string("<OBJECT><ID>box</ID><TYPE>FIXED</TYPE><SHAPE>BOX</SHAPE>"
                                             "<DIMS>0.2,0.2,0.2</DIMS><POS>1.75,0.05,0.105</POS>"
                                             "<COLOR>0.85,0.1,0.1</COLOR></OBJECT>")
                               : std::string()) +
                          flush_plate(1.95, 0.05, yaw));
      const Eigen::Vector3d plate = looked.in_base(1.95, 0.05);
      const auto judged = af::find_flush_plate(looked.frame, af::KurtGeometry{});
      ASSERT_TRUE(judged) << "yaw " << yaw << ", box " << box;
      EXPECT_NEAR(judged->x, plate.x(), 0.05) << "yaw " << yaw << ", box " << box;
      EXPECT_NEAR(judged->y, plate.y(), 0.03) << "yaw " << yaw << ", box " << box;
      const double a = yaw * M_PI / 180;
      EXPECT_NEAR(judged->half_extent, 0.2 * (std::cos(a) + std::sin(a)), 0.03) << "yaw " << yaw;
    }
  }
}

TEST(KurtDemoVision, AFlushPlatePartlyOutOfViewOrAbsentIsNotJudged) {
  // Its near edge below the picture (0.9 m ahead), then one side out of it, then none at all.
  for (const auto& [x, y] : {std::pair{0.9, 0.0}, std::pair{1.8, 0.9}}) {
    const Looked looked(flush_plate(x, y));
    EXPECT_FALSE(af::find_flush_plate(looked.frame, af::KurtGeometry{})) << x << "," << y;
  }
  const Looked empty("");
  EXPECT_FALSE(af::find_flush_plate(empty.frame, af::KurtGeometry{}));
}

TEST(KurtDemoVision, SeesNothingInAnEmptyRoomAndNothingWithoutAStereoMatch) {
  World world(load_world_string("<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT></WORLD>",
                                "empty.xml"));
  world.robot("kurt")->execute(macsim::robot::CraneTarget{M_PI / 2, 0.6, 0.0}, world.time());
  run_for(world, 2.0);
  auto frame = stereo(world);
  EXPECT_TRUE(macsim::affordances::find_objects(frame, macsim::affordances::KurtGeometry{}).empty());
  // A red can drawn into the left image only: no partner in the right one, no sighting.
  cv::rectangle(frame.left, cv::Rect(150, 150, 12, 24), cv::Scalar(25, 25, 215), cv::FILLED);
  EXPECT_TRUE(macsim::affordances::find_objects(frame, macsim::affordances::KurtGeometry{}).empty());
}

}  // namespace
}  // namespace macsim::test
