#include "ways.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "macsim/affordances/perception.h"

namespace kurt_navigate {

namespace af = macsim::affordances;

namespace {

constexpr double kCell = 0.1;  // m: the sightings' cells

}  // namespace

double height_above_floor(const std::array<float, 3>& point) {
  return point[2] + af::SensorMount{}.base_height;
}

macsim::client::Cloud along(const macsim::client::Cloud& cloud, double heading) {
  macsim::client::Cloud way;
  way.stamp = cloud.stamp;
  way.points.reserve(cloud.points.size());
  const double c = std::cos(heading), s = std::sin(heading);
  for (const auto& q : cloud.points) {
    way.points.push_back(
        {static_cast<float>(c * q[0] + s * q[1]), static_cast<float>(-s * q[0] + c * q[1]), q[2]});
  }
  return way;
}

std::map<std::string, double> way_features(const macsim::client::Cloud& way) {
  af::Percept p;
  af::perceive_cloud(way, af::SensorMount{}, p);
  return af::named_features(p, af::Affordance::Traverse);
}

std::vector<Point2> tall_structure(const macsim::client::Cloud& cloud,
                                   const kurt_loop::Pose2& pose) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  std::map<std::pair<int, int>, Point2> cells;
  for (const auto& q : cloud.points) {
    const double h = height_above_floor(q);
    if (h < 0.05 || h > 0.6 || std::hypot(q[0], q[1]) < 0.6 || std::hypot(q[0], q[1]) > 6) continue;
    const double x = pose.x + c * q[0] - s * q[1], y = pose.y + s * q[0] + c * q[1];
    cells.try_emplace(
        {static_cast<int>(std::floor(x / 0.05)), static_cast<int>(std::floor(y / 0.05))},
        Point2{x, y});
  }
  std::vector<Point2> points;
  for (const auto& [cell, p] : cells) points.push_back(p);
  return points;
}

std::optional<std::array<double, 2>> align(const std::vector<Point2>& before,
                                           const std::vector<Point2>& now,
                                           const std::vector<std::array<double, 2>>& guesses) {
  if (before.size() < 30 || now.size() < 30) return std::nullopt;
  // Each point of `before` with the normal of the line its neighbours (within 0.2 m) make.
  std::vector<Eigen::Vector2d> normals(before.size(), Eigen::Vector2d::Zero());
  std::vector<bool> on_line(before.size(), false);
  for (std::size_t i = 0; i < before.size(); ++i) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    std::vector<Eigen::Vector2d> near;
    for (const auto& q : before) {
      const Eigen::Vector2d d(q[0] - before[i][0], q[1] - before[i][1]);
      if (d.norm() < 0.2) near.emplace_back(q[0], q[1]);
    }
    if (near.size() < 3) continue;
    for (const auto& q : near) mean += q;
    mean /= static_cast<double>(near.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& q : near) cov += (q - mean) * (q - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(cov);
    if (solver.eigenvalues()[1] > 4 * solver.eigenvalues()[0]) {  // a line, not a blob
      normals[i] = solver.eigenvectors().col(0);
      on_line[i] = true;
    }
  }
  // From each guess (and from none), the fit that matches the most points closely.
  std::optional<std::array<double, 2>> best_fit;
  int best_matched = 0;
  std::vector<std::array<double, 2>> starts{{0.0, 0.0}};
  starts.insert(starts.end(), guesses.begin(), guesses.end());
  for (const auto& start : starts) {
    Eigen::Vector2d shift(start[0], start[1]);
    int matched = 0;
    bool determined = true;
    for (double gate : {0.3, 0.2, 0.1, 0.1, 0.1, 0.05, 0.05, 0.05}) {
      Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
      Eigen::Vector2d b = Eigen::Vector2d::Zero();
      matched = 0;
      for (const auto& p : now) {
        const Eigen::Vector2d moved = Eigen::Vector2d(p[0], p[1]) + shift;
        std::size_t best = 0;
        double nearest = 1e9;
        for (std::size_t i = 0; i < before.size(); ++i) {
          const double d = std::hypot(before[i][0] - moved.x(), before[i][1] - moved.y());
          if (d < nearest) nearest = d, best = i;
        }
        if (nearest > gate) continue;
        const Eigen::Vector2d gap = Eigen::Vector2d(before[best][0], before[best][1]) - moved;
        if (on_line[best]) {  // point to line: n . (moved + delta - q) = 0
          const Eigen::Vector2d& n = normals[best];
          a += n * n.transpose();
          b += n * n.dot(gap);
        } else {  // point to point
          a += Eigen::Matrix2d::Identity();
          b += gap;
        }
        ++matched;
      }
      // Both directions must be seen (walls across and along): else the shift is not determined.
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(a);
      if (matched < 30 || solver.eigenvalues()[0] < 3) {
        determined = false;
        break;
      }
      shift += a.ldlt().solve(b);
    }
    if (determined && matched > best_matched) {
      best_matched = matched;
      best_fit = std::array<double, 2>{shift.x(), shift.y()};
    }
  }
  return best_fit;
}

af::AffordanceModel load_traverse_model(const std::string& dir) {
  const std::string file = dir + "/traverse.yml";
  auto model = af::AffordanceModel::load(file);  // its errors name the file
  const auto& info = model.info();
  if (info.affordance != "traverse")
    throw std::runtime_error(file + " is a model of " + info.affordance + ", not traverse");
  if (std::find(info.labels.begin(), info.labels.end(), "traversable") == info.labels.end())
    throw std::runtime_error(file + " has no label 'traversable'");
  const auto& cloud = *af::feature_group("cloud");
  const auto& shape = *af::feature_group("shape");
  std::string other;
  for (const auto& f : info.features) {
    if (std::find(cloud.begin(), cloud.end(), f) == cloud.end() &&
        std::find(shape.begin(), shape.end(), f) == shape.end())
      other += (other.empty() ? "" : ",") + f;
  }
  if (!other.empty()) {
    throw std::runtime_error(file + " takes " + other +
                             ", which a cloud does not give (the navigator judges what stands in "
                             "its way from the 3D laser only; train with affordance_learn "
                             "--features shape; cloud and cloud,shape are taken too)");
  }
  return model;
}

void Sightings::add(const macsim::client::Cloud& cloud, const kurt_loop::Pose2& pose) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  for (const auto& q : cloud.points) {
    const double h = height_above_floor(q);
    if (h <= kAboveFloor || h > af::GroundGrid::kTop || std::hypot(q[0], q[1]) > 3.0 ||
        std::hypot(q[0], q[1]) < 0.3)
      continue;
    const double x = pose.x + c * q[0] - s * q[1], y = pose.y + s * q[0] + c * q[1];
    ++cells_[{static_cast<int>(std::floor(x / kCell)), static_cast<int>(std::floor(y / kCell))}];
  }
}

void Sightings::pass(const kurt_loop::Pose2& pose) {
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
    if (std::hypot(x1 - x0 + 1, y1 - y0 + 1) * kCell > 1.2) continue;  // a wall
    ++counts.seen;
    double nearest = 1e9;
    for (const auto& [cx, cy] : thing) {
      const double x = (cx + 0.5) * kCell, y = (cy + 0.5) * kCell;
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
