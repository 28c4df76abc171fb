// What a renderer needs of a world: a copy of every visible shape's pose, size and looks.
#pragma once

#include <string>
#include <vector>

#include "macsim/sim_core/world.h"

namespace macsim::render {

/// A robot's frames the camera modes need.
struct RobotView {
  std::string name;
  Pose base_link;
  Pose left_camera, right_camera;  ///< optical centres; x forward, y left, z up
};

/// A copy of what can be seen, taken on the simulation thread; renderers never touch ODE.
struct Scene {
  double time = 0.0;
  std::vector<ShapeView> shapes;
  std::vector<RobotView> robots;
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Constant(-3), bounds_max = Eigen::Vector3d::Constant(3);
};

/// Stereo camera mounts on the KURT3D (ours: a 0.12 m baseline on a mast 0.42 m above
/// base_link, looking 15 degrees down over the crane), in base_link.
Pose left_camera_mount();
Pose right_camera_mount();

/// Copies the world's objects and robots into a Scene (call on the simulation thread).
Scene capture_scene(const World& world);

}  // namespace macsim::render
