#include "ways.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "macsim/affordances/perception.h"

namespace kurt_navigate {

namespace af = macsim::affordances;

namespace {

constexpr double kSightingCell = 0.1;  // m: the sightings' cells

}  // namespace

void Sightings::add(const macsim::client::Cloud& cloud, const macsim::affordances::Pose2& pose) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  for (const auto& q : cloud.points) {
    const double h = height_above_floor(q);
    if (h <= kAboveFloor || h > af::GroundGrid::kTop || std::hypot(q[0], q[1]) > 3.0 ||
        std::hypot(q[0], q[1]) < 0.3)
      continue;
    const double x = pose.x + c * q[0] - s * q[1], y = pose.y + s * q[0] + c * q[1];
    ++cells_[{static_cast<int>(std::floor(x / kSightingCell)),
              static_cast<int>(std::floor(y / kSightingCell))}];
  }
}

void Sightings::pass(const macsim::affordances::Pose2& pose) {
  if (path_.empty() || std::hypot(pose.x - path_.back().first, pose.y - path_.back().second) > 0.02)
    path_.emplace_back(pose.x, pose.y);
}

Sightings::Counts Sightings::count(double half_width) const {
  Counts counts;
  std::map<std::pair<int, int>, bool> grouped;
  for (const auto& [cell, n] : cells_) {
    if (grouped.count(cell)) continue;
    // One thing: the cells touching each other (8 neighbours).
    std::vector<std::pair<int, int>> thing, todo{cell};
    grouped[cell] = true;
    while (!todo.empty()) {
      const auto at = todo.back();
      todo.pop_back();
      thing.push_back(at);
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          const std::pair<int, int> next{at.first + dx, at.second + dy};
          if (cells_.count(next) && !grouped.count(next)) {
            grouped[next] = true;
            todo.push_back(next);
          }
        }
      }
    }
    int x0 = thing.front().first, x1 = x0, y0 = thing.front().second, y1 = y0;
    for (const auto& [x, y] : thing) {
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    if (std::hypot(x1 - x0 + 1, y1 - y0 + 1) * kSightingCell > 1.2) continue;  // a wall
    ++counts.seen;
    double nearest = 1e9;
    for (const auto& [cx, cy] : thing) {
      const double x = (cx + 0.5) * kSightingCell, y = (cy + 0.5) * kSightingCell;
      for (const auto& [px, py] : path_) nearest = std::min(nearest, std::hypot(x - px, y - py));
    }
    if (nearest < half_width)
      ++counts.through;
    else if (nearest < 1.0)
      ++counts.around;
  }
  return counts;
}

}  // namespace kurt_navigate
