// The seed's camera modes, as camera poses for a viewer or a snapshot.
#pragma once

#include <optional>
#include <string>

#include "macsim/sim_core/scene.h"

namespace macsim::render {

/// MACSim's viewer modes (SimulatorInterface::CameraMode).
enum class CameraMode {
  MouseOnly,      ///< free camera moved with the mouse
  MouseKeyboard,  ///< free camera, mouse plus w/a/s/d
  FixedFollow,    ///< camera stays put, always facing the robot
  Follow,         ///< camera keeps its distance and direction to the robot, facing it
  Inside,         ///< fixed inside the robot, looking ahead
  LeftCamera,     ///< the robot's left camera
  RightCamera,    ///< the robot's right camera
  Manual,         ///< moved only by the program
  Chase,          ///< high behind the robot, looking at the floor ahead of it
};

/// The mode of that name ("MouseOnly", ..., case-insensitive), if any.
std::optional<CameraMode> camera_mode_from_name(const std::string& name);
std::string camera_mode_name(CameraMode mode);

/// A pose at `eye` looking at `target` (x forward, z as close to up as it can be).
Pose look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

/// Where a mode puts the camera for `scene` (the first robot is followed). `free_camera` is the
/// user's camera for the free modes and FixedFollow's position; without it, an overview.
Pose camera_pose(CameraMode mode, const Scene& scene, const std::optional<Pose>& free_camera = {});

}  // namespace macsim::render
