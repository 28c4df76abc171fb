// What a renderer needs of a world: a copy of every visible shape and of each robot's frames,
// taken on the simulation thread. Renderers read this description, never the world.
#pragma once

#include <string>
#include <vector>

#include "macsim/sim_core/world_spec.h"

namespace macsim {

class World;

/// A robot's frames the camera modes need.
struct RobotView {
  std::string name;
  Pose base_link;
  bool has_cameras = false;        ///< its type has a stereo pair (else both are base_link)
  Pose left_camera, right_camera;  ///< optical centres; x forward, y left, z up
};

/// A copy of what can be seen.
struct Scene {
  double time = 0.0;
  std::vector<ShapeView> shapes;
  std::vector<RobotView> robots;
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Constant(-3),
                  bounds_max = Eigen::Vector3d::Constant(3);
};

/// Copies the world's objects and robots into a Scene (on the simulation thread).
Scene capture_scene(const World& world);

}  // namespace macsim
