// The floor of a world seen from above: what stands where, and whether a robot gets between
// two points; for tests that judge a layout from its specification without playing it.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "macsim/sim_core/world_spec.h"

namespace macsim::test {

/// The floor of a world seen from above on a 4 cm grid: what stands on each cell, and whether
/// a robot of a given half width can get from one point to another between it.
class FloorMap {
 public:
  static constexpr double kCell = 0.04;
  FloorMap(double x0, double y0, double x1, double y1)
      : x0_(x0), y0_(y0), columns_(static_cast<int>((x1 - x0) / kCell)),
        rows_(static_cast<int>((y1 - y0) / kCell)),
        blocked_(static_cast<std::size_t>(columns_ * rows_), 0) {}

  /// Marks the cells under every component of `object` taller than 1 cm; with
  /// `without_traversable`, not those a robot drives over or pushes away (a whole portable
  /// object, or a part no higher than 6 cm).
  void add(const ObjectSpec& object, bool without_traversable) {
    distance_.clear();
    for (const auto& c : object.components) {
      const Pose pose = object.pose * c.pose;
      const Eigen::Vector3d axis = pose.orientation * Eigen::Vector3d::UnitZ();
      const bool upright = std::fabs(axis.z()) > 0.99;
      Eigen::Vector3d half;  // the component's box in its own frame
      if (c.shape == Shape::Box)
        half = c.size / 2;
      else if (c.shape == Shape::Cylinder)
        half = {c.size[0], c.size[0], c.size[2] / 2};
      else
        half = Eigen::Vector3d::Constant(c.size[0]);
      // Its corners on the floor; its top.
      std::vector<Eigen::Vector2d> corners;
      double top = -1e9;
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner((k & 1 ? 1 : -1) * half.x(), (k & 2 ? 1 : -1) * half.y(),
                                     (k & 4 ? 1 : -1) * half.z());
        const Eigen::Vector3d at = pose.position + pose.orientation * corner;
        top = std::max(top, at.z());
        corners.push_back(at.head<2>());
      }
      if (c.shape == Shape::Sphere) top = pose.position.z() + c.size[0];
      if (top < 0.01) continue;  // a mark on the floor
      if (without_traversable && (object.portable || top <= 0.06)) continue;
      // Round things standing (or any sphere) cover a disc; the rest the hull of their corners.
      const bool disc = c.shape == Shape::Sphere || (c.shape == Shape::Cylinder && upright);
      const Eigen::Vector2d centre = pose.position.head<2>();
      const auto hull = convex_hull(corners);
      double xa = 1e9, xb = -1e9, ya = 1e9, yb = -1e9;
      for (const auto& q : corners) {
        xa = std::min(xa, q.x()), xb = std::max(xb, q.x());
        ya = std::min(ya, q.y()), yb = std::max(yb, q.y());
      }
      for (int i = std::max(0, column(xa)); i <= std::min(columns_ - 1, column(xb)); ++i) {
        for (int j = std::max(0, row(ya)); j <= std::min(rows_ - 1, row(yb)); ++j) {
          const Eigen::Vector2d p(x0_ + (i + 0.5) * kCell, y0_ + (j + 0.5) * kCell);
          const bool under = disc ? (p - centre).norm() <= c.size[0] + kCell / 2
                                  : inside(hull, p, kCell / 2);
          if (under) blocked_[index(i, j)] = 1;
        }
      }
    }
  }

  /// Whether a disc of `radius` gets from `from` to `to` (or within `within` of it) without
  /// touching what was added.
  bool connected(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double radius,
                 double within = 0) const {
    // Distance to the nearest blocked cell (8-neighbour chamfer, 3 per side, 4 per diagonal,
    // kept until something is added), then a flood fill through the cells far enough from
    // everything.
    const std::vector<int>& d = distances();
    const int clear = static_cast<int>(std::ceil(3 * radius / kCell));
    std::vector<char> seen(blocked_.size(), 0);
    std::vector<std::pair<int, int>> todo{{column(from.x()), row(from.y())}};
    const std::pair<int, int> goal{column(to.x()), row(to.y())};
    while (!todo.empty()) {
      const auto [i, j] = todo.back();
      todo.pop_back();
      if (i < 0 || i >= columns_ || j < 0 || j >= rows_) continue;
      const std::size_t k = index(i, j);
      if (seen[k] || d[k] < clear) continue;
      seen[k] = 1;
      if (std::pair{i, j} == goal) return true;
      const Eigen::Vector2d centre(x0_ + (i + 0.5) * kCell, y0_ + (j + 0.5) * kCell);
      if (within > 0 && (centre - to).norm() <= within) return true;
      todo.insert(todo.end(), {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}});
    }
    return false;
  }

  /// The chamfer distance of every cell to the nearest blocked one (computed once per map).
  const std::vector<int>& distances() const {
    if (!distance_.empty()) return distance_;
    const int far = 1 << 20;
    std::vector<int> d(blocked_.size());
    for (std::size_t k = 0; k < d.size(); ++k) d[k] = blocked_[k] ? 0 : far;
    auto at = [&](int i, int j) {
      return i < 0 || i >= columns_ || j < 0 || j >= rows_ ? far : d[index(i, j)];
    };
    for (int j = 0; j < rows_; ++j) {
      for (int i = 0; i < columns_; ++i) {
        int& v = d[index(i, j)];
        v = std::min({v, at(i - 1, j) + 3, at(i, j - 1) + 3, at(i - 1, j - 1) + 4,
                      at(i + 1, j - 1) + 4});
      }
    }
    for (int j = rows_ - 1; j >= 0; --j) {
      for (int i = columns_ - 1; i >= 0; --i) {
        int& v = d[index(i, j)];
        v = std::min({v, at(i + 1, j) + 3, at(i, j + 1) + 3, at(i + 1, j + 1) + 4,
                      at(i - 1, j + 1) + 4});
      }
    }
    distance_ = std::move(d);
    return distance_;
  }

 private:
  /// The convex hull of points, counter-clockwise (Andrew's monotone chain).
  static std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
    std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) {
      return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    });
    auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
    };
    std::vector<Eigen::Vector2d> hull(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 1e-12) --k;
      hull[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
      while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 1e-12) --k;
      hull[k++] = p[i];
    }
    hull.resize(k > 1 ? k - 1 : k);
    return hull;
  }
  /// Whether `p` lies in the convex polygon `hull` grown by `margin`.
  static bool inside(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p,
                     double margin) {
    for (std::size_t i = 0; i < hull.size(); ++i) {
      const Eigen::Vector2d a = hull[i], b = hull[(i + 1) % hull.size()];
      const Eigen::Vector2d edge = b - a;
      const double length = edge.norm();
      if (length < 1e-12) continue;
      // Outward distance (counter-clockwise: the outside is to the right of each edge).
      const double out = (edge.x() * (p - a).y() - edge.y() * (p - a).x()) / -length;
      if (out > margin) return false;
    }
    return true;
  }
  int column(double x) const { return static_cast<int>(std::floor((x - x0_) / kCell)); }
  int row(double y) const { return static_cast<int>(std::floor((y - y0_) / kCell)); }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j * columns_ + i); }
  double x0_, y0_;
  int columns_, rows_;
  std::vector<char> blocked_;
  mutable std::vector<int> distance_;
};

}  // namespace macsim::test
