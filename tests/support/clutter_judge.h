// What a run through clutter did to it, judged from the world state (for tests and benchmarks,
// never for a controller): a thing is driven through when the robot pushed it 5 cm or more or
// its footprint crossed where the thing stood, driven around when the robot passed within 1 m
// without touching it.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "macsim/msg/macsim_msgs.h"

namespace macsim::test {

/// The things of worlds/clutter_field.xml (user data "clutter").
inline constexpr int kClutterFieldThings = 17;

/// Points of an object's components on a 2 cm lattice, projected onto the floor.
inline std::vector<Eigen::Vector2d> footprint(const macsim_msgs::msg::dds_::Object_& o) {
  namespace mm = macsim_msgs::msg::dds_;
  auto quaternion = [](const auto& q) { return Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()); };
  auto vector = [](const auto& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); };
  const Eigen::Quaterniond q = quaternion(o.pose().orientation());
  const Eigen::Vector3d p = vector(o.pose().position());
  std::vector<Eigen::Vector2d> points;
  for (const auto& c : o.components()) {
    const Eigen::Vector3d size(c.size()[0], c.size()[1], c.size()[2]);
    Eigen::Vector3d half;  // box: sizes; cylinder: radius, -, height; sphere: radius
    if (c.shape() == mm::SHAPE_BOX)
      half = size / 2;
    else if (c.shape() == mm::SHAPE_CYLINDER)
      half = {size[0], size[0], size[2] / 2};
    else
      half = Eigen::Vector3d::Constant(size[0]);
    const Eigen::Quaterniond cq = q * quaternion(c.pose().orientation());
    const Eigen::Vector3d cp = p + q * vector(c.pose().position());
    for (double x = -half.x(); x <= half.x() + 1e-9; x += 0.02)
      for (double y = -half.y(); y <= half.y() + 1e-9; y += 0.02)
        for (double z = -half.z(); z <= half.z() + 1e-9; z += 0.02)
          points.push_back((cp + cq * Eigen::Vector3d(x, y, z)).head<2>());
  }
  return points;
}

/// The things (objects with user data "clutter") driven through and around.
struct ClutterJudgement {
  std::set<std::string> through, around;

  /// `before` and `after`: the objects by name; `path`: the robot's middle (ground truth);
  /// `half_width`: half the robot's width.
  ClutterJudgement(const std::map<std::string, macsim_msgs::msg::dds_::Object_>& before,
                   const std::map<std::string, macsim_msgs::msg::dds_::Object_>& after,
                   const std::vector<Eigen::Vector2d>& path, double half_width = 0.22) {
    for (const auto& [name, was] : before) {
      if (was.user_data() != "clutter" || !after.count(name)) continue;
      const auto& now = after.at(name).pose().position();
      const bool pushed = std::hypot(now.x() - was.pose().position().x(),
                                     now.y() - was.pose().position().y()) >= 0.05;
      double nearest = 1e9;
      const auto shape = footprint(was);
      for (const auto& at : path)
        for (const auto& point : shape) nearest = std::min(nearest, (at - point).norm());
      if (pushed || nearest < half_width)
        through.insert(name);
      else if (nearest < 1.0)
        around.insert(name);
    }
  }

  /// The kind of a clutter_field thing: its name up to the last '_' ("box_a": "box").
  static std::string kind(const std::string& name) { return name.substr(0, name.rfind('_')); }
  /// Whether a name in `set` starts with one of `prefixes`.
  static bool any_of(const std::set<std::string>& set,
                     std::initializer_list<const char*> prefixes) {
    for (const auto& name : set)
      for (const char* p : prefixes)
        if (name.rfind(p, 0) == 0) return true;
    return false;
  }
};

}  // namespace macsim::test
