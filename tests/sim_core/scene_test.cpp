// The scene description a renderer reads: shapes and each robot's frames, its cameras from its
// type's configuration (a KURT2 has none).
#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/scene.h"

#include <gtest/gtest.h>

#include "support/world_helpers.h"

namespace macsim::test {
namespace {

TEST(Scene, RobotsCarryTheCamerasOfTheirType) {
  World world(load_world_string(R"(<WORLD>
      <ROBOT><ID>k3</ID><TYPE>kurt3d</TYPE></ROBOT>
      <ROBOT><ID>k2</ID><TYPE>kurt2</TYPE><POS>2,0,0</POS></ROBOT></WORLD>)",
                                "two.xml"));
  const Scene scene = capture_scene(world);
  ASSERT_EQ(scene.robots.size(), 2u);
  const RobotView& k3 = scene.robots[0];
  EXPECT_TRUE(k3.has_cameras);
  EXPECT_NEAR((k3.left_camera.position - k3.right_camera.position).norm(), 0.12, 1e-12);
  const Pose expected = k3.base_link * world.robot_as<KurtRobot>("k3")->config().cameras->left;
  EXPECT_TRUE(k3.left_camera.position.isApprox(expected.position, 1e-12));
  const RobotView& k2 = scene.robots[1];
  EXPECT_FALSE(k2.has_cameras);
  EXPECT_FALSE(world.robot_as<KurtRobot>("k2")->config().cameras.has_value());
  EXPECT_EQ(scene.shapes.size(), world.shapes().size());
  EXPECT_EQ(scene.time, world.time());
}

}  // namespace
}  // namespace macsim::test
