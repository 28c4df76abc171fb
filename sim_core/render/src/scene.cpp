#include "macsim/render/scene.h"

namespace macsim::render {

Pose left_camera_mount() {
  return {{0.05, 0.06, 0.42},
          Eigen::Quaterniond(Eigen::AngleAxisd(15 * M_PI / 180, Eigen::Vector3d::UnitY()))};
}

Pose right_camera_mount() {
  return {{0.05, -0.06, 0.42},
          Eigen::Quaterniond(Eigen::AngleAxisd(15 * M_PI / 180, Eigen::Vector3d::UnitY()))};
}

Scene capture_scene(const World& world) {
  Scene scene;
  scene.time = world.time();
  scene.shapes = world.shapes();
  for (const auto& robot : world.robots()) {
    const Pose base = robot->base_link_pose();
    scene.robots.push_back({robot->name(), base, base * left_camera_mount(), base * right_camera_mount()});
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

}  // namespace macsim::render
