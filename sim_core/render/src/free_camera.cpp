#include <algorithm>

#include "macsim/render/viewer.h"

namespace macsim::render {

namespace {
constexpr double kRadiansPerPixel = 0.005;
constexpr double kMetresPerPixel = 0.01;
}  // namespace

Pose FreeCamera::pose() const {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY());
  return {position, q};
}

FreeCamera FreeCamera::from_pose(const Pose& pose) {
  const Eigen::Vector3d forward = pose.orientation * Eigen::Vector3d::UnitX();
  FreeCamera c;
  c.position = pose.position;
  c.yaw = std::atan2(forward.y(), forward.x());
  c.pitch = -std::asin(std::clamp(forward.z(), -1.0, 1.0));
  return c;
}

void FreeCamera::drag(MouseButton button, double dx, double dy) {
  const Eigen::Vector3d ahead(std::cos(yaw), std::sin(yaw), 0);
  const Eigen::Vector3d left(-std::sin(yaw), std::cos(yaw), 0);
  switch (button) {
    case MouseButton::Left:
      yaw -= dx * kRadiansPerPixel;
      pitch = std::clamp(pitch + dy * kRadiansPerPixel, -1.5, 1.5);
      break;
    case MouseButton::Right:
      position += ahead * (-dy * kMetresPerPixel) + left * (-dx * kMetresPerPixel);
      break;
    case MouseButton::Middle:
      position.z() = std::max(0.05, position.z() - dy * kMetresPerPixel);
      position += left * (-dx * kMetresPerPixel);
      break;
  }
}

bool FreeCamera::key(char key, double step) {
  const Eigen::Vector3d ahead(std::cos(yaw), std::sin(yaw), 0);
  const Eigen::Vector3d left(-std::sin(yaw), std::cos(yaw), 0);
  switch (key) {
    case 'w': position += ahead * step; return true;
    case 's': position -= ahead * step; return true;
    case 'a': position += left * step; return true;
    case 'd': position -= left * step; return true;
    default: return false;
  }
}

}  // namespace macsim::render
