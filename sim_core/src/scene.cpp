#include "macsim/sim_core/scene.h"

#include "macsim/sim_core/world.h"

namespace macsim {

Scene capture_scene(const World& world) {
  Scene scene;
  scene.time = world.time();
  scene.shapes = world.shapes();
  for (const auto& robot : world.robots()) {
    const Pose base = robot->base_link_pose();
    RobotView view{robot->name(), base, false, base, base};
    if (const auto cameras = robot->cameras()) {
      view.has_cameras = true;
      view.left_camera = base * cameras->left;
      view.right_camera = base * cameras->right;
    }
    scene.robots.push_back(view);
  }
  if (!scene.shapes.empty()) {
    scene.bounds_min = scene.bounds_max = scene.shapes.front().pose.position;
    for (const auto& s : scene.shapes) {
      scene.bounds_min = scene.bounds_min.cwiseMin(s.pose.position);
      scene.bounds_max = scene.bounds_max.cwiseMax(s.pose.position);
    }
  }
  return scene;
}

}  // namespace macsim
