#include "macsim/affordances/laser_map.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace macsim::affordances {

std::vector<Point> slice(const macsim::client::Cloud& cloud, const KurtGeometry& g, double low,
                         double high, double near, double far) {
  std::vector<Point> out;
  for (const auto& p : cloud.points) {
    const double height = p[2] + g.base_height;
    const double range = std::hypot(p[0], p[1]);
    if (height >= low && height <= high && range >= near && range <= far) {
      out.push_back({p[0], p[1]});
    }
  }
  return out;
}

namespace {

/// A line through `point` along the unit vector `dir`.
struct Line {
  Point point, dir;
  double distance(const Point& p) const {
    return std::fabs((p.x - point.x) * dir.y - (p.y - point.y) * dir.x);
  }
  double along(const Point& p) const { return (p.x - point.x) * dir.x + (p.y - point.y) * dir.y; }
};

/// The least-squares line through `points` (principal axis).
Line fit(const std::vector<Point>& points) {
  double mx = 0, my = 0;
  for (const auto& p : points) {
    mx += p.x;
    my += p.y;
  }
  mx /= points.size();
  my /= points.size();
  double sxx = 0, sxy = 0, syy = 0;
  for (const auto& p : points) {
    sxx += (p.x - mx) * (p.x - mx);
    sxy += (p.x - mx) * (p.y - my);
    syy += (p.y - my) * (p.y - my);
  }
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  return {{mx, my}, {std::cos(angle), std::sin(angle)}};
}

}  // namespace

std::optional<Passage> find_passage(const std::vector<Point>& points, double min_width,
                                    int min_wall_points) {
  if (static_cast<int>(points.size()) < min_wall_points) return std::nullopt;
  constexpr double kOnLine = 0.04, kNearLine = 0.2;
  std::mt19937 rng(7);  // the same cloud gives the same answer
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  std::vector<Point> best;
  for (int i = 0; i < 400; ++i) {
    const Point a = points[pick(rng)], b = points[pick(rng)];
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    if (length < 0.3) continue;
    const Line line{a, {(b.x - a.x) / length, (b.y - a.y) / length}};
    std::vector<Point> inliers;
    for (const auto& p : points) {
      if (line.distance(p) < kOnLine) inliers.push_back(p);
    }
    if (inliers.size() > best.size()) best = std::move(inliers);
  }
  if (static_cast<int>(best.size()) < min_wall_points) return std::nullopt;
  const Line wall = fit(best);
  std::vector<double> along;
  for (const auto& p : points) {
    if (wall.distance(p) < kNearLine) along.push_back(wall.along(p));
  }
  std::sort(along.begin(), along.end());
  std::optional<Passage> passage;
  for (std::size_t i = 1; i < along.size(); ++i) {
    const double gap = along[i] - along[i - 1];
    if (gap < min_width || (passage && gap <= passage->width)) continue;
    const double middle = 0.5 * (along[i] + along[i - 1]);
    Passage p;
    p.centre = {wall.point.x + middle * wall.dir.x, wall.point.y + middle * wall.dir.y};
    p.normal = {-wall.dir.y, wall.dir.x};
    if (p.normal.x * p.centre.x + p.normal.y * p.centre.y < 0) p.normal = {-p.normal.x, -p.normal.y};
    p.width = gap;
    p.wall_points = static_cast<int>(best.size());
    passage = p;
  }
  return passage;
}

bool corridor_free(const std::vector<Point>& points, Point goal, double half_width, double spare) {
  const double length = std::hypot(goal.x, goal.y);
  if (length < 1e-6) return true;
  const Point dir{goal.x / length, goal.y / length};
  for (const auto& p : points) {
    if (std::hypot(p.x - goal.x, p.y - goal.y) < spare) continue;
    const double along = p.x * dir.x + p.y * dir.y;
    const double across = std::fabs(p.x * dir.y - p.y * dir.x);
    if (along > 0 && along < length && across < half_width) return false;
  }
  return true;
}

namespace {
constexpr double kCell = 0.05;
int cell(double v) { return static_cast<int>(std::floor(v / kCell)); }
}  // namespace

void ObstacleMap::add(const macsim::client::Cloud& cloud, const KurtGeometry& g, double x,
                      double y, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  for (const Point& p : slice(cloud, g, 0.04, 0.45, 0.45, 4.0)) {
    const int64_t k = key(cell(x + c * p.x - s * p.y), cell(y + s * p.x + c * p.y));
    if (!passable_.count(k)) cells_.insert(k);
  }
}

std::vector<Point> ObstacleMap::obstacles_near(Point a, Point b, double reach) const {
  std::vector<Point> out;
  const double x0 = std::min(a.x, b.x) - reach, x1 = std::max(a.x, b.x) + reach;
  const double y0 = std::min(a.y, b.y) - reach, y1 = std::max(a.y, b.y) + reach;
  for (const int64_t k : cells_) {
    const int ix = static_cast<int>(k >> 32), iy = static_cast<int>(static_cast<int32_t>(k & 0xffffffff));
    const Point c{(ix + 0.5) * kCell, (iy + 0.5) * kCell};
    if (c.x >= x0 && c.x <= x1 && c.y >= y0 && c.y <= y1) out.push_back(c);
  }
  return out;
}

void ObstacleMap::block(Point at, double radius) {
  const int r = static_cast<int>(std::ceil(radius / kCell));
  for (int ix = cell(at.x) - r; ix <= cell(at.x) + r; ++ix) {
    for (int iy = cell(at.y) - r; iy <= cell(at.y) + r; ++iy) {
      if (std::hypot((ix + 0.5) * kCell - at.x, (iy + 0.5) * kCell - at.y) > radius) continue;
      passable_.erase(key(ix, iy));
      cells_.insert(key(ix, iy));
    }
  }
}

void ObstacleMap::let_pass(Point at) {
  const int64_t k = key(cell(at.x), cell(at.y));
  passable_.insert(k);
  cells_.erase(k);
}

void ObstacleMap::clear(Point at, double radius) {
  const int r = static_cast<int>(std::ceil(radius / kCell));
  for (int ix = cell(at.x) - r; ix <= cell(at.x) + r; ++ix) {
    for (int iy = cell(at.y) - r; iy <= cell(at.y) + r; ++iy) {
      if (std::hypot((ix + 0.5) * kCell - at.x, (iy + 0.5) * kCell - at.y) <= radius)
        cells_.erase(key(ix, iy));
    }
  }
}

double ObstacleMap::clearance(Point at, double limit, Point except, double spare) const {
  const int r = static_cast<int>(std::ceil(limit / kCell));
  double nearest = limit;
  for (int ix = cell(at.x) - r; ix <= cell(at.x) + r; ++ix) {
    for (int iy = cell(at.y) - r; iy <= cell(at.y) + r; ++iy) {
      if (!cells_.count(key(ix, iy))) continue;
      const double cx = (ix + 0.5) * kCell, cy = (iy + 0.5) * kCell;
      if (std::hypot(cx - except.x, cy - except.y) < spare) continue;
      nearest = std::min(nearest, std::hypot(cx - at.x, cy - at.y));
    }
  }
  return nearest;
}

bool ObstacleMap::free(Point a, Point b, double half_width, Point except, double spare) const {
  const double length = std::hypot(b.x - a.x, b.y - a.y);
  const int steps = std::max(1, static_cast<int>(std::ceil(length / kCell)));
  for (int i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    const Point p{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    if (clearance(p, half_width, except, spare) < half_width) return false;
  }
  return true;
}

std::optional<Point> ObstacleMap::first_blocked(Point a, Point b, double half_width) const {
  const double length = std::hypot(b.x - a.x, b.y - a.y);
  const int steps = std::max(1, static_cast<int>(std::ceil(length / kCell)));
  const int r = static_cast<int>(std::ceil(half_width / kCell));
  for (int i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    const Point p{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    std::optional<Point> nearest;
    double best = half_width;
    for (int ix = cell(p.x) - r; ix <= cell(p.x) + r; ++ix) {
      for (int iy = cell(p.y) - r; iy <= cell(p.y) + r; ++iy) {
        if (!cells_.count(key(ix, iy))) continue;
        const Point centre{(ix + 0.5) * kCell, (iy + 0.5) * kCell};
        const double d = std::hypot(centre.x - p.x, centre.y - p.y);
        if (d < best) best = d, nearest = centre;
      }
    }
    if (nearest) return nearest;
  }
  return std::nullopt;
}

}  // namespace macsim::affordances
