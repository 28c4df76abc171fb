// Offscreen rendering against known scenes: colours where objects are, depth, textures, the
// stereo pair's disparity, every camera mode, and the render thread.
#include "macsim/images/image_files.h"
#include "macsim/render/renderer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "macsim/render/camera_modes.h"
#include "macsim/render/camera_rig.h"
#include "macsim/render/viewer.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

using macsim::Scene;
using render::CameraIntrinsics;
using render::CameraMode;
using render::OffscreenRenderer;

// A scene with one box of `color` centred 2 m ahead of a camera at the origin.
Scene box_ahead(const Color& color, const std::string& texture = "") {
  Scene scene;
  scene.shapes.push_back({Shape::Box, {0.5, 0.5, 0.5}, at(2.0, 0.0, 1.0), color, texture});
  return scene;
}

const Pose kCamera = at(0.0, 0.0, 1.0);  // looking along +x, 1 m above the floor

TEST(Renderer, DrawsAnObjectWhereItIsWithItsColourAndDepth) {
  OffscreenRenderer renderer(320, 240);
  CameraIntrinsics in;
  in.width = 320;
  in.height = 240;
  cv::Mat depth;
  const cv::Mat image = renderer.render(box_ahead({0.9f, 0.1f, 0.1f, 1}), kCamera, in, &depth);
  ASSERT_EQ(image.type(), CV_8UC3);
  ASSERT_EQ(image.size(), cv::Size(320, 240));
  const cv::Vec3b centre = image.at<cv::Vec3b>(120, 160);  // BGR
  EXPECT_GT(centre[2], 2 * centre[1]);                     // red dominates where the box is
  EXPECT_GT(centre[2], 2 * centre[0]);
  EXPECT_NEAR(depth.at<float>(120, 160), 1.75, 0.01);  // the box's near face
  // Above the box: sky, far away.
  EXPECT_GT(depth.at<float>(5, 160), 50.0f);
  const cv::Vec3b sky = image.at<cv::Vec3b>(5, 160);
  EXPECT_GT(sky[0], sky[2]);  // bluish
  // Below the horizon on the left: the floor at a finite depth.
  EXPECT_LT(depth.at<float>(235, 10), 10.0f);
}

TEST(Renderer, TexturesShowOnObjects) {
  OffscreenRenderer renderer(320, 240);
  CameraIntrinsics in;
  in.width = 320;
  in.height = 240;
  const std::string stripes = source("worlds/DemoEnvironment_v1/textures/stripes.bmp");
  const cv::Mat image = renderer.render(box_ahead({1, 1, 1, 1}, stripes), kCamera, in);
  // Across the box's face the red and white stripes alternate.
  int red = 0, white = 0;
  for (int x = 130; x < 190; ++x) {
    const cv::Vec3b p = image.at<cv::Vec3b>(120, x);
    red += p[2] > 2 * p[1] && p[2] > 60;                         // lit red stripe
    white += p[1] > 60 && std::abs(int(p[2]) - int(p[1])) < 30;  // lit white stripe
  }
  EXPECT_GT(red, 5);
  EXPECT_GT(white, 5);
}

TEST(Renderer, TexturesNotDrawnLatelyAreDroppedBeyondTheCapAndReadAgainWhenNeeded) {
  OffscreenRenderer renderer(64, 48);
  CameraIntrinsics in;
  in.width = 64;
  in.height = 48;
  const std::string dir = ::testing::TempDir() + "texture_cap_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  auto solid = [&](const std::string& name, const cv::Scalar& bgr) {
    const std::string file = dir + "/" + name + ".bmp";
    EXPECT_TRUE(macsim::images::write_image(file, cv::Mat(8, 8, CV_8UC3, bgr)));
    return file;
  };
  auto centre = [&](const std::string& texture) {
    return renderer.render(box_ahead({1, 1, 1, 1}, texture), kCamera, in).at<cv::Vec3b>(24, 32);
  };
  const std::string first = solid("first", {0, 0, 255});  // red
  const cv::Vec3b red = centre(first);
  ASSERT_GT(red[2], 2 * red[0]);
  // Kept while it is among the last drawn: the file changed on disk is not read again.
  solid("first", {255, 0, 0});  // blue
  EXPECT_GT(centre(first)[2], 2 * centre(first)[0]);
  // 64 others drawn since (the cap; all in one scene, so none of them goes while drawn): the
  // first is the least recently drawn and goes; drawn again, it is read again.
  Scene many;
  for (int i = 0; i < 64; ++i) {
    many.shapes.push_back({Shape::Box,
                           {0.1, 0.1, 0.1},
                           at(3.0, -1.0 + i * 0.03, 1.0),
                           {1, 1, 1, 1},
                           solid("other" + std::to_string(i), {0, 255, 0})});
  }
  renderer.render(many, kCamera, in);
  const cv::Vec3b blue = centre(first);
  EXPECT_GT(blue[0], 2 * blue[2]);
  std::filesystem::remove_all(dir);
}

// render_into() draws into the caller's image: its storage is kept from frame to frame while
// nobody else holds it, and an image somebody kept is never drawn over.
TEST(Renderer, RenderingIntoAnImageReusesItsStorageButNeverOneSomebodyKept) {
  OffscreenRenderer renderer(320, 240);
  CameraIntrinsics in;
  in.width = 320;
  in.height = 240;
  auto red_at_centre = [](const cv::Mat& image) {
    const cv::Vec3b p = image.at<cv::Vec3b>(120, 160);  // BGR
    return p[2] > 2 * p[1] && p[2] > 2 * p[0];
  };
  cv::Mat image;
  renderer.render_into(image, box_ahead({0.9f, 0.1f, 0.1f, 1}), kCamera, in);
  ASSERT_EQ(image.size(), cv::Size(320, 240));
  ASSERT_TRUE(red_at_centre(image));
  const uchar* storage = image.data;
  renderer.render_into(image, box_ahead({0.1f, 0.1f, 0.9f, 1}), kCamera, in);
  EXPECT_EQ(image.data, storage);  // unshared: drawn over in place
  EXPECT_FALSE(red_at_centre(image));

  renderer.render_into(image, box_ahead({0.9f, 0.1f, 0.1f, 1}), kCamera, in);
  const cv::Mat kept = image;  // a consumer holds this frame
  renderer.render_into(image, box_ahead({0.1f, 0.1f, 0.9f, 1}), kCamera, in);
  EXPECT_NE(image.data, kept.data);
  EXPECT_TRUE(red_at_centre(kept));  // still the frame it kept
  EXPECT_FALSE(red_at_centre(image));
}

TEST(Renderer, TheStereoPairSeesDisparity) {
  World world(shipped_world("DemoWorld_v1.xml"));
  // A tall blue marker 1.5 m ahead of the robot's cameras.
  ObjectSpec marker = primitive(Shape::Box, {0.1, 0.1, 1.0}, {-0.45, 0.0, 0.5}, false);
  marker.components[0].color = {0.05f, 0.05f, 1.0f, 1};
  ASSERT_TRUE(world.edit().create_object(marker).ok());
  const Scene scene = capture_scene(world);
  OffscreenRenderer renderer(320, 240);
  CameraIntrinsics in;
  in.width = 320;
  in.height = 240;
  auto marker_column = [&](const cv::Mat& image) {
    double sum = 0;
    int n = 0;
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(100, x);
      if (p[0] > 3 * p[2] && p[0] > 3 * p[1] && p[0] > 60) {  // the blue marker
        sum += x;
        ++n;
      }
    }
    return n ? sum / n : -1.0;
  };
  const cv::Mat left_image = renderer.render(scene, scene.robots[0].left_camera, in);
  const cv::Mat right_image = renderer.render(scene, scene.robots[0].right_camera, in);
  const double left = marker_column(left_image);
  const double right = marker_column(right_image);
  ASSERT_GT(left, 0);
  ASSERT_GT(right, 0);
  // Disparity = focal * baseline / depth: 289.7 px * 0.12 m / 1.5 m = 23 px (320x240, 45 deg).
  EXPECT_NEAR(left - right, in.focal() * 0.12 / 1.5, 4.0);
}

TEST(CameraModes, EveryModeHasANameAndAPose) {
  World world(shipped_world("DemoWorld_v1.xml"));
  const Scene scene = capture_scene(world);
  OffscreenRenderer renderer(160, 120);
  CameraIntrinsics in;
  in.width = 160;
  in.height = 120;
  for (const char* name : {"MouseOnly", "MouseKeyboard", "FixedFollow", "Follow", "Inside",
                           "LeftCamera", "RightCamera", "Manual"}) {
    auto mode = render::camera_mode_from_name(name);
    ASSERT_TRUE(mode.has_value()) << name;
    EXPECT_EQ(render::camera_mode_name(*mode), name);
    const Pose pose = render::camera_pose(*mode, scene);
    EXPECT_TRUE(pose.position.allFinite()) << name;
    cv::Mat gray;
    cv::Mat image = renderer.render(scene, pose, in);
    cv::Scalar mean, stddev;
    cv::meanStdDev(image, mean, stddev);
    EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 20) << name << ": a featureless image";
  }
  EXPECT_FALSE(render::camera_mode_from_name("Fisheye").has_value());
  // Follow keeps behind the robot; FixedFollow stays put but faces it.
  const Eigen::Vector3d robot = scene.robots[0].base_link.position;
  const Pose follow = render::camera_pose(CameraMode::Follow, scene);
  EXPECT_LT(follow.position.x(), robot.x());
  const Pose fixed = render::camera_pose(CameraMode::FixedFollow, scene);
  const Eigen::Vector3d facing = fixed.orientation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(facing.dot((robot - fixed.position).normalized()), 1.0, 1e-9);
}

TEST(FreeCamera, MouseAndKeysMoveItAsTheSeedsViewerDid) {
  render::FreeCamera camera;
  camera.position = {0, 0, 2};
  camera.yaw = 0;
  camera.pitch = 0;
  camera.drag(render::MouseButton::Right, 0, -100);  // right button, mouse up: forwards
  EXPECT_NEAR(camera.position.x(), 1.0, 1e-12);
  camera.drag(render::MouseButton::Right, -100, 0);  // mouse left: to the left
  EXPECT_NEAR(camera.position.y(), 1.0, 1e-12);
  camera.drag(render::MouseButton::Middle, 0, -50);  // middle button, mouse up: rises
  EXPECT_NEAR(camera.position.z(), 2.5, 1e-12);
  camera.drag(render::MouseButton::Left, -100, 60);  // left button: turns left, tilts down
  EXPECT_NEAR(camera.yaw, 0.5, 1e-12);
  EXPECT_NEAR(camera.pitch, 0.3, 1e-12);
  const Eigen::Vector3d before = camera.position;
  EXPECT_TRUE(camera.key('w', 0.1));
  EXPECT_NEAR((camera.position - before).norm(), 0.1, 1e-12);
  EXPECT_NEAR(camera.position.z(), before.z(), 1e-12);  // stays in its plane
  EXPECT_FALSE(camera.key('x'));
  // A pose and back.
  const render::FreeCamera again = render::FreeCamera::from_pose(camera.pose());
  EXPECT_NEAR(again.yaw, camera.yaw, 1e-12);
  EXPECT_NEAR(again.pitch, camera.pitch, 1e-12);
}

TEST(CameraRig, RendersOnItsOwnThreadAndKeepsTheNewestScene) {
  World world(shipped_world("DemoWorld_v1.xml"));
  CameraIntrinsics in;
  in.width = 320;
  in.height = 240;
  std::mutex mutex;
  std::vector<render::CameraImage> frames;
  render::CameraRig rig("kurt", in, [&](const render::CameraImage& f) {
    std::lock_guard<std::mutex> lock(mutex);
    frames.push_back(f);
  });
  for (int i = 0; i < 5; ++i) {
    run_for(world, 0.05);
    rig.submit(capture_scene(world));  // never blocks the physics
  }
  rig.wait_idle();
  std::lock_guard<std::mutex> lock(mutex);
  EXPECT_EQ(rig.rendered() + rig.dropped(), 5u);
  ASSERT_EQ(frames.size(), 2 * rig.rendered());  // left, then right, of every scene rendered
  EXPECT_NEAR(frames.back().stamp, 0.25, 1e-9);  // the newest scene is always rendered
  EXPECT_EQ(frames[frames.size() - 2].eye, render::Eye::Left);
  EXPECT_EQ(frames.back().eye, render::Eye::Right);
  EXPECT_EQ(frames[frames.size() - 2].stamp, frames.back().stamp);
  EXPECT_EQ(frames[frames.size() - 2].image.size(), cv::Size(320, 240));
  EXPECT_EQ(frames.back().image.size(), cv::Size(320, 240));
}

}  // namespace
}  // namespace macsim::test
