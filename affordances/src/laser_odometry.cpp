#include "macsim/affordances/laser_odometry.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>

namespace macsim::affordances {

std::vector<Point2> static_structure(const macsim::client::Cloud& cloud,
                                     const Pose2& pose) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  std::map<std::pair<int, int>, Point2> cells;
  for (const auto& q : cloud.points) {
    const double h = height_above_floor(q);
    const double range = std::hypot(q[0], q[1]);
    if (h < kStaticHeight || h > 0.6 || range < 0.6 || range > 9.5) continue;
    const double x = pose.x + c * q[0] - s * q[1], y = pose.y + s * q[0] + c * q[1];
    cells.try_emplace(cell_of({x, y}), Point2{x, y});
  }
  std::vector<Point2> points;
  for (const auto& [cell, p] : cells) points.push_back(p);
  return points;
}

void StaticMap::add(const std::vector<Point2>& points) {
  for (const auto& p : points) {
    if (cells_.try_emplace(cell_of(p), points_.size()).second) points_.push_back(p);
  }
}

namespace {

/// The map's points by 0.3 m cell, for the nearest one to a point within 0.3 m.
class NearestIndex {
 public:
  explicit NearestIndex(const std::vector<Point2>& points) : points_(points) {
    for (std::size_t i = 0; i < points.size(); ++i)
      cells_[key(points[i][0], points[i][1])].push_back(i);
  }
  /// The nearest point within kReach of (x, y) and its distance, or nullopt.
  std::optional<std::pair<std::size_t, double>> nearest(double x, double y) const {
    const auto [i0, j0] = key(x, y);
    std::optional<std::pair<std::size_t, double>> best;
    for (int i = i0 - 1; i <= i0 + 1; ++i)
      for (int j = j0 - 1; j <= j0 + 1; ++j) {
        const auto cell = cells_.find({i, j});
        if (cell == cells_.end()) continue;
        for (std::size_t k : cell->second) {
          const double d = std::hypot(points_[k][0] - x, points_[k][1] - y);
          if (d <= kReach && (!best || d < best->second)) best = {{k, d}};
        }
      }
    return best;
  }
  static constexpr double kReach = 0.3;

 private:
  static std::pair<int, int> key(double x, double y) {
    return {static_cast<int>(std::floor(x / kReach)), static_cast<int>(std::floor(y / kReach))};
  }
  const std::vector<Point2>& points_;
  std::map<std::pair<int, int>, std::vector<std::size_t>> cells_;
};

}  // namespace

std::optional<std::array<double, 2>> align(const std::vector<Point2>& map,
                                           const std::vector<Point2>& now,
                                           const std::vector<std::array<double, 2>>& guesses) {
  if (map.size() < 30 || now.size() < 30) return std::nullopt;
  const NearestIndex index(map);
  // Each point of the map with the normal of the line its neighbours (within 0.2 m) make.
  std::vector<Eigen::Vector2d> normals(map.size(), Eigen::Vector2d::Zero());
  std::vector<bool> on_line(map.size(), false);
  for (std::size_t i = 0; i < map.size(); ++i) {
    std::vector<Eigen::Vector2d> near;
    for (const auto& q : map)
      if (std::hypot(q[0] - map[i][0], q[1] - map[i][1]) < 0.2) near.emplace_back(q[0], q[1]);
    if (near.size() < 3) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
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
  // The map point nearest a point (within 0.3 m).
  struct Match {
    std::size_t index;
    double distance;
  };
  const auto match = [&](const Eigen::Vector2d& p) -> std::optional<Match> {
    const auto found = index.nearest(p.x(), p.y());
    if (!found) return std::nullopt;
    return Match{found->first, found->second};
  };
  // From `p` to the map point it matched: the gap, and its length across the line there.
  const auto gap_to = [&](const Match& m, const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return Eigen::Vector2d(map[m.index][0], map[m.index][1]) - p;
  };
  const auto residual = [&](const Match& m, const Eigen::Vector2d& p) {
    return on_line[m.index] ? std::fabs(normals[m.index].dot(gap_to(m, p))) : m.distance;
  };
  // Each fit's cost: the sum of its points' squared residuals (to the line there, if one), each
  // at most kOutlier (a point of what moved, or seen anew, costs the same wherever it is laid).
  constexpr double kOutlier = 0.15;
  struct Fit {
    Eigen::Vector2d shift;
    double cost;
  };
  const auto fit = [&](Eigen::Vector2d shift) -> std::optional<Fit> {
    for (double gate : {0.3, 0.2, 0.1, 0.1, 0.1, 0.05, 0.05, 0.05}) {
      Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
      Eigen::Vector2d b = Eigen::Vector2d::Zero();
      int matched = 0;
      for (const auto& p : now) {
        const Eigen::Vector2d moved = Eigen::Vector2d(p[0], p[1]) + shift;
        const auto m = match(moved);
        if (!m || m->distance > gate) continue;
        const Eigen::Vector2d gap = gap_to(*m, moved);
        if (on_line[m->index]) {  // point to line: n . (moved + delta - q) = 0
          const Eigen::Vector2d& n = normals[m->index];
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
      if (matched < 30 || solver.eigenvalues()[0] < 3) return std::nullopt;
      shift += a.ldlt().solve(b);
    }
    double cost = 0;
    for (const auto& p : now) {
      const Eigen::Vector2d moved = Eigen::Vector2d(p[0], p[1]) + shift;
      const auto m = match(moved);
      const double r = m ? std::min(kOutlier, residual(*m, moved)) : kOutlier;
      cost += r * r;
    }
    return Fit{shift, cost};
  };
  // From no shift (the wheels' word), then from each guess: a guess must fit clearly better than
  // the wheels' word to be taken instead.
  std::optional<Fit> best = fit(Eigen::Vector2d::Zero());
  for (const auto& g : guesses) {
    const auto f = fit(Eigen::Vector2d(g[0], g[1]));
    if (f && (!best || f->cost < 0.8 * best->cost)) best = f;
  }
  // The wheels slipped further than one fit reaches: fits from starts 0.2 m apart around them,
  // the one laying the points best taken when most of them lie on the map.
  if (!best) {
    for (double dx = -kSearch; dx <= kSearch + 1e-9; dx += 0.2)
      for (double dy = -kSearch; dy <= kSearch + 1e-9; dy += 0.2) {
        const auto f = fit(Eigen::Vector2d(dx, dy));
        if (f && (!best || f->cost < best->cost)) best = f;
      }
    const double mean = best ? std::sqrt(best->cost / static_cast<double>(now.size())) : kOutlier;
    if (mean > 0.06) return std::nullopt;
  }
  if (!best) return std::nullopt;
  return std::array<double, 2>{best->shift.x(), best->shift.y()};
}

}  // namespace macsim::affordances
