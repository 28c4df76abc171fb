#include "macsim/affordances/traverse.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <stdexcept>

#include "macsim/affordances/perception.h"

namespace macsim::affordances {

namespace {

// What lies closer than this is one thing (the scanner's rings leave wider gaps far away; the
// robot passes no gap this narrow).
double gap(double range) { return std::max(0.15, 0.1 * range); }

/// The robot's own body in base_link (tracks, crane base): its returns are not things.
bool on_body(const std::array<float, 3>& q) {
  return std::fabs(q[0]) < 0.36 && std::fabs(q[1]) < 0.3;
}

}  // namespace

double height_above_floor(const std::array<float, 3>& point) {
  return point[2] + SensorMount{}.base_height;
}

std::pair<int, int> cell_of(const Point2& p) {
  return {static_cast<int>(std::floor(p[0] / kGrid)), static_cast<int>(std::floor(p[1] / kGrid))};
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
  Percept p;
  perceive_cloud(way, SensorMount{}, p);
  return named_features(p, Affordance::Traverse);
}

AffordanceModel load_traverse_model(const std::string& dir) {
  const std::string file = dir + "/traverse.yml";
  auto model = AffordanceModel::load(file);  // its errors name the file
  const auto& info = model.info();
  if (info.affordance != "traverse")
    throw std::runtime_error(file + " is a model of " + info.affordance + ", not traverse");
  if (std::find(info.labels.begin(), info.labels.end(), "traversable") == info.labels.end())
    throw std::runtime_error(file + " has no label 'traversable'");
  const auto& cloud = *feature_group("cloud");
  const auto& shape = *feature_group("shape");
  std::string other;
  for (const auto& f : info.features) {
    if (std::find(cloud.begin(), cloud.end(), f) == cloud.end() &&
        std::find(shape.begin(), shape.end(), f) == shape.end())
      other += (other.empty() ? "" : ",") + f;
  }
  if (!other.empty()) {
    throw std::runtime_error(file + " takes " + other +
                             ", which a cloud does not give (the robot judges what stands in "
                             "its way from the 3D laser only; train with affordance_learn "
                             "--features shape; cloud and cloud,shape are taken too)");
  }
  return model;
}

std::vector<Thing> things_in(const macsim::client::Cloud& cloud, const Pose2& pose,
                             double range) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  using Key = std::pair<int, int>;
  std::map<Key, std::vector<std::size_t>> cells;
  std::map<Key, double> top;  // per cell: its highest return above the floor
  for (std::size_t k = 0; k < cloud.points.size(); ++k) {
    const auto& q = cloud.points[k];
    const double h = height_above_floor(q);
    if (!(h > kAboveFloor) || on_body(q) || !(std::hypot(q[0], q[1]) <= range)) continue;
    const double x = pose.x + c * q[0] - s * q[1], y = pose.y + s * q[0] + c * q[1];
    const auto key = cell_of({x, y});
    auto [t, fresh] = top.try_emplace(key, h);
    if (!fresh) t->second = std::max(t->second, h);
    if (h <= GroundGrid::kTop) cells[key].push_back(k);
  }
  // A cell is as high as its highest return, and things are grouped by height: low cells (a
  // joist, a doorstep's bar) make things of their own, so that a joist beside a log or a box is
  // judged apart from it (a low cell next to a higher one is the foot of that one); cells higher
  // than a trial's view (a wall) make things the model is not asked about.
  std::map<Key, Height> level;
  for (const auto& [key, h] : top) {
    cells.try_emplace(key);  // a wall's cell may have no return within the view
    if (h > GroundGrid::kTop) {
      level[key] = Height::Towering;
      continue;
    }
    bool is_low = h < kLowThing;
    for (int dx = -1; dx <= 1 && is_low; ++dx)
      for (int dy = -1; dy <= 1 && is_low; ++dy) {
        const auto n = top.find({key.first + dx, key.second + dy});
        is_low = n == top.end() || n->second < kLowThing;
      }
    level[key] = is_low ? Height::Low : Height::High;
  }
  // A wall's cells whose returns did not reach above the view (its top not seen there) are the
  // wall's still: what lies within 10 cm of a wall is taken as part of it.
  const auto near_wall = [&](const Key& key) {
    for (int dx = -2; dx <= 2; ++dx)
      for (int dy = -2; dy <= 2; ++dy) {
        const auto n = level.find({key.first + dx, key.second + dy});
        if (n != level.end() && n->second == Height::Towering) return true;
      }
    return false;
  };
  std::vector<Key> foot;
  for (const auto& [key, h] : level)
    if (h != Height::Towering && near_wall(key)) foot.push_back(key);
  for (const auto& key : foot) level[key] = Height::Towering;
  std::vector<Thing> things;
  std::map<Key, bool> grouped;
  for (const auto& [start, unused] : cells) {
    if (grouped.count(start)) continue;
    // One thing: the cells less than a gap apart.
    Thing thing;
    thing.height = level.at(start);
    std::vector<Key> todo{start};
    grouped[start] = true;
    int x0 = start.first, x1 = x0, y0 = start.second, y1 = y0;
    while (!todo.empty()) {
      const auto at = todo.back();
      todo.pop_back();
      const Point2 centre{(at.first + 0.5) * kGrid, (at.second + 0.5) * kGrid};
      thing.cells.push_back(centre);
      const auto& points = cells.at(at);
      thing.points.insert(thing.points.end(), points.begin(), points.end());
      x0 = std::min(x0, at.first), x1 = std::max(x1, at.first);
      y0 = std::min(y0, at.second), y1 = std::max(y1, at.second);
      const int n =
          static_cast<int>(gap(std::hypot(centre[0] - pose.x, centre[1] - pose.y)) / kGrid);
      for (int dx = -n; dx <= n; ++dx) {
        for (int dy = -n; dy <= n; ++dy) {
          const Key next{at.first + dx, at.second + dy};
          if (dx * dx + dy * dy <= n * n && cells.count(next) && !grouped.count(next) &&
              level.at(next) == thing.height) {
            grouped[next] = true;
            todo.push_back(next);
          }
        }
      }
    }
    thing.across = std::hypot(x1 - x0 + 1, y1 - y0 + 1) * kGrid;
    thing.distance = std::numeric_limits<double>::infinity();
    for (const auto& p : thing.cells) {
      thing.centre[0] += p[0] / static_cast<double>(thing.cells.size());
      thing.centre[1] += p[1] / static_cast<double>(thing.cells.size());
      thing.distance = std::min(thing.distance, std::hypot(p[0] - pose.x, p[1] - pose.y));
    }
    things.push_back(std::move(thing));
  }
  return things;
}

macsim::client::Cloud without_others(const macsim::client::Cloud& cloud,
                                     const std::vector<Thing>& things, const Thing& kept) {
  std::vector<char> drop(cloud.points.size(), 0);
  for (const auto& thing : things) {
    if (&thing == &kept || thing.points.size() < 3) continue;
    for (std::size_t k : thing.points) drop[k] = 1;
  }
  macsim::client::Cloud seen;
  seen.stamp = cloud.stamp;
  for (std::size_t k = 0; k < cloud.points.size(); ++k)
    if (!drop[k]) seen.points.push_back(cloud.points[k]);
  return seen;
}

FloorPlan::FloorPlan(const Point2& from, const Point2& to, double border, double cell)
    : from_(from), to_(to), cell_(cell) {
  x0_ = std::min(from[0], to[0]) - border;
  y0_ = std::min(from[1], to[1]) - border;
  columns_ = static_cast<int>(std::ceil((std::max(from[0], to[0]) + border - x0_) / cell));
  rows_ = static_cast<int>(std::ceil((std::max(from[1], to[1]) + border - y0_) / cell));
  cost_.assign(static_cast<std::size_t>(columns_) * rows_, 1.0f);
  blocked_.assign(cost_.size(), 0);
}

int FloorPlan::column(double x) const { return static_cast<int>(std::floor((x - x0_) / cell_)); }
int FloorPlan::row(double y) const { return static_cast<int>(std::floor((y - y0_) / cell_)); }
Point2 FloorPlan::centre(int i, int j) const {
  return {x0_ + (i + 0.5) * cell_, y0_ + (j + 0.5) * cell_};
}

void FloorPlan::add(const Thing& thing, double clearance, double margin, double passable_cost,
                    double unknown_cost) {
  const bool dear = !thing.judged || thing.passable;  // crossed at a price
  const double reach = dear ? 0.15 : margin;
  const int n = static_cast<int>(std::ceil(reach / cell_));
  for (const auto& p : thing.cells) {
    const int ci = column(p[0]), cj = row(p[1]);
    for (int di = -n; di <= n; ++di) {
      for (int dj = -n; dj <= n; ++dj) {
        const int i = ci + di, j = cj + dj;
        if (!inside(i, j)) continue;
        const auto at = centre(i, j);
        const double d = std::hypot(at[0] - p[0], at[1] - p[1]);
        if (d > reach) continue;
        float& cost = cost_[index(i, j)];
        if (dear) {
          cost = std::max(cost, static_cast<float>(thing.judged ? passable_cost : unknown_cost));
        } else if (d < clearance) {
          blocked_[index(i, j)] = 1;
        } else {
          cost = std::max(cost, static_cast<float>(1 + 4 * (margin - d) / (margin - clearance)));
        }
      }
    }
  }
}

void FloorPlan::block(const Point2& at, double radius) {
  const int n = static_cast<int>(std::ceil(radius / cell_));
  const int ci = column(at[0]), cj = row(at[1]);
  for (int i = ci - n; i <= ci + n; ++i) {
    for (int j = cj - n; j <= cj + n; ++j) {
      const auto c = centre(i, j);
      if (inside(i, j) && std::hypot(c[0] - at[0], c[1] - at[1]) <= radius)
        blocked_[index(i, j)] = 1;
    }
  }
}

std::vector<Point2> FloorPlan::path(double escape) const {
  const int si = column(from_[0]), sj = row(from_[1]), gi = column(to_[0]), gj = row(to_[1]);
  if (!inside(si, sj) || !inside(gi, gj)) return {};
  const auto may_enter = [&](int i, int j) {
    if (!blocked_[index(i, j)]) return true;
    const auto c = centre(i, j);
    return std::hypot(c[0] - from_[0], c[1] - from_[1]) < escape;
  };
  if (!may_enter(gi, gj)) return {};
  const auto heuristic = [&](int i, int j) { return std::hypot(i - gi, j - gj) * cell_; };
  std::vector<double> best(cost_.size(), std::numeric_limits<double>::infinity());
  std::vector<int> came(cost_.size(), -1);
  using Entry = std::pair<double, int>;  // estimate, cell
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const int start = static_cast<int>(index(si, sj)), goal = static_cast<int>(index(gi, gj));
  best[start] = 0;
  open.emplace(heuristic(si, sj), start);
  while (!open.empty()) {
    const auto [estimate, at] = open.top();
    open.pop();
    if (at == goal) break;
    const int i = at % columns_, j = at / columns_;
    if (estimate > best[at] + heuristic(i, j) + 1e-6) continue;  // an older entry
    for (int di = -1; di <= 1; ++di) {
      for (int dj = -1; dj <= 1; ++dj) {
        const int ni = i + di, nj = j + dj;
        if ((di == 0 && dj == 0) || !inside(ni, nj) || !may_enter(ni, nj)) continue;
        const int next = static_cast<int>(index(ni, nj));
        // Blocked cells near the start (it stands against something) are left at a price.
        const float dear = blocked_[next] ? 5.0f : 1.0f;
        const double step = std::hypot(di, dj) * cell_ * (cost_[at] + cost_[next]) / 2 * dear;
        if (best[at] + step < best[next]) {
          best[next] = best[at] + step;
          came[next] = at;
          open.emplace(best[next] + heuristic(ni, nj), next);
        }
      }
    }
  }
  if (came[goal] < 0 && goal != start) return {};
  std::vector<Point2> way;
  for (int at = goal; at >= 0; at = came[at]) way.push_back(centre(at % columns_, at / columns_));
  std::reverse(way.begin(), way.end());
  way.front() = from_;
  way.back() = to_;
  return way;
}

double length(const std::vector<Point2>& way) {
  double sum = 0;
  for (std::size_t k = 1; k < way.size(); ++k)
    sum += std::hypot(way[k][0] - way[k - 1][0], way[k][1] - way[k - 1][1]);
  return sum;
}

double near_side(const macsim::client::Cloud& cloud, const Pose2& pose, const Thing& thing) {
  // Along the bearing of its middle, of its returns within 0.3 m of that line.
  const double bearing =
      std::atan2(thing.centre[1] - pose.y, thing.centre[0] - pose.x) - pose.yaw;
  const double c = std::cos(bearing), s = std::sin(bearing);
  double near = std::hypot(thing.centre[0] - pose.x, thing.centre[1] - pose.y);
  for (std::size_t k : thing.points) {
    const auto& q = cloud.points[k];
    if (std::fabs(-s * q[0] + c * q[1]) < 0.3) near = std::min(near, c * q[0] + s * q[1]);
  }
  return near;
}

double p_traversable(const AffordanceModel& model, const macsim::client::Cloud& cloud,
                     const Pose2& pose, const std::vector<Thing>& things, const Thing& thing) {
  const double off = wrap(std::atan2(thing.centre[1] - pose.y, thing.centre[0] - pose.x) - pose.yaw);
  const auto said = model.predict(way_features(along(without_others(cloud, things, thing), off)));
  return said.label == "traversable" ? said.confidence : 1 - said.confidence;
}

}  // namespace macsim::affordances
