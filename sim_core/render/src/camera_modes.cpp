#include "macsim/render/camera_modes.h"

#include <algorithm>
#include <array>
#include <cctype>

namespace macsim::render {

namespace {

const std::array<std::pair<CameraMode, const char*>, 9> kNames{{
    {CameraMode::MouseOnly, "MouseOnly"},
    {CameraMode::MouseKeyboard, "MouseKeyboard"},
    {CameraMode::FixedFollow, "FixedFollow"},
    {CameraMode::Follow, "Follow"},
    {CameraMode::Inside, "Inside"},
    {CameraMode::LeftCamera, "LeftCamera"},
    {CameraMode::RightCamera, "RightCamera"},
    {CameraMode::Manual, "Manual"},
    {CameraMode::Chase, "Chase"},
}};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

/// An overview from the south-west, above, facing the middle of the scene.
Pose overview(const Scene& scene) {
  const Eigen::Vector3d centre = (scene.bounds_min + scene.bounds_max) / 2;
  const double size = std::max(2.0, (scene.bounds_max - scene.bounds_min).head<2>().norm());
  const Eigen::Vector3d eye = centre + Eigen::Vector3d(-0.3, -0.55, 0.5) * size;
  return look_at(eye, {centre.x(), centre.y(), 0.0});
}

}  // namespace

std::optional<CameraMode> camera_mode_from_name(const std::string& name) {
  for (const auto& [mode, text] : kNames) {
    if (lower(text) == lower(name)) return mode;
  }
  return std::nullopt;
}

std::string camera_mode_name(CameraMode mode) {
  for (const auto& [m, text] : kNames) {
    if (m == mode) return text;
  }
  return "?";
}

Pose look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  Eigen::Vector3d x = target - eye;
  if (x.norm() < 1e-9) x = Eigen::Vector3d::UnitX();
  x.normalize();
  Eigen::Vector3d y = Eigen::Vector3d::UnitZ().cross(x);
  if (y.norm() < 1e-6) y = Eigen::Vector3d::UnitY();  // looking straight up or down
  y.normalize();
  const Eigen::Vector3d z = x.cross(y);
  Eigen::Matrix3d r;
  r << x, y, z;
  return {eye, Eigen::Quaterniond(r)};
}

Pose camera_pose(CameraMode mode, const Scene& scene, const std::optional<Pose>& free_camera) {
  const Pose free = free_camera ? *free_camera : overview(scene);
  if (scene.robots.empty()) return free;
  const RobotView& robot = scene.robots.front();
  switch (mode) {
    case CameraMode::MouseOnly:
    case CameraMode::MouseKeyboard:
    case CameraMode::Manual:
      return free;
    case CameraMode::FixedFollow:
      return look_at(free.position, robot.base_link.position);
    case CameraMode::Follow: {
      // Behind and above, at a fixed distance and direction in the robot's frame.
      const Eigen::Vector3d eye = robot.base_link.position + robot.base_link.orientation * Eigen::Vector3d(-1.6, 0.0, 1.0);
      return look_at(eye, robot.base_link.position + robot.base_link.orientation * Eigen::Vector3d(0.6, 0, 0));
    }
    case CameraMode::Chase: {
      // High behind the robot, looking at the floor ahead of it: what it works on.
      const Pose& b = robot.base_link;
      return look_at(b.position + b.orientation * Eigen::Vector3d(-2.0, 0.5, 2.3),
                     b.position + b.orientation * Eigen::Vector3d(0.5, 0.1, -0.1));
    }
    case CameraMode::Inside:
      return robot.base_link * Pose{{0.0, 0.0, 0.2}, Eigen::Quaterniond::Identity()};
    case CameraMode::LeftCamera:
      return robot.left_camera;
    case CameraMode::RightCamera:
      return robot.right_camera;
  }
  return free;
}

}  // namespace macsim::render
