// What the KURT's 3D laser cloud shows of the demonstrator: the tall wall that splits the room,
// the passage a door leaves open in it, and whether a straight way is free.
#pragma once

#include <cstdint>
#include <optional>
#include <unordered_set>
#include <vector>

#include "macsim/affordances/kurt_geometry.h"
#include "macsim/client/robot_devices.h"

namespace macsim::affordances {

struct Point {
  double x = 0, y = 0;
};

/// The points of `cloud` (base_link) whose height above the floor is in [low, high] and that lie
/// between `near` and `far` of the robot's centre, flattened to x, y.
std::vector<Point> slice(const macsim::client::Cloud& cloud, const KurtGeometry& geometry,
                         double low, double high, double near, double far);

/// An opening in a wall, in the frame of the points.
struct Passage {
  Point centre;          ///< the middle of the opening, on the wall's line
  Point normal;          ///< unit vector across the wall, pointing away from the origin
  double width = 0;      ///< m
  int wall_points = 0;   ///< points on the wall's line
};

/// The wall is the line most points lie on (RANSAC, then a least-squares fit); its points and
/// those close in front of or behind it (a door leaf) are ordered along it, and the widest gap
/// of at least `min_width` between neighbours is the passage. Nothing when no wall of at least
/// `min_wall_points` points or no such gap is found.
std::optional<Passage> find_passage(const std::vector<Point>& points, double min_width,
                                    int min_wall_points = 40);

/// True if no point lies in the straight corridor of half-width `half_width` from the origin to
/// `goal`, apart from points within `spare` of the goal (the object that is the goal itself).
bool corridor_free(const std::vector<Point>& points, Point goal, double half_width, double spare);

/// Where the laser saw things to keep clear of (between 4 and 45 cm above the floor: cans,
/// boxes, posts, walls, the switch), gathered from clouds taken at known poses, on a 5 cm grid
/// in the odometry frame.
class ObstacleMap {
 public:
  /// Adds a cloud taken with base_link at (x, y, yaw).
  void add(const macsim::client::Cloud& cloud, const KurtGeometry& geometry, double x, double y,
           double yaw);
  /// Forgets what was within `radius` of (x, y) (a can that was carried away).
  void clear(Point at, double radius);
  /// The cell holding `at` is no obstacle from now on, whatever later clouds show (it holds
  /// something judged traversable).
  void let_pass(Point at);
  /// The cells within `radius` of `at` are obstacles from now on, whatever was let pass there
  /// (something the robot stalled against).
  void block(Point at, double radius);
  /// Distance from `at` to the nearest obstacle (up to `limit`), ignoring those within `spare`
  /// of `except`.
  double clearance(Point at, double limit, Point except = {1e9, 1e9}, double spare = 0) const;
  /// True if the whole segment a-b keeps `half_width` from every obstacle, apart from those
  /// within `spare` of `except`.
  bool free(Point a, Point b, double half_width, Point except = {1e9, 1e9},
            double spare = 0) const;
  /// The middle of the first obstacle cell within `half_width` of the segment a-b, going from a;
  /// nothing when the segment is free.
  std::optional<Point> first_blocked(Point a, Point b, double half_width) const;
  std::size_t cells() const { return cells_.size(); }
  /// The middles of the obstacle cells within `reach` of the segment a-b's bounding box.
  std::vector<Point> obstacles_near(Point a, Point b, double reach) const;

 private:
  static int64_t key(int ix, int iy) { return (int64_t(ix) << 32) ^ uint32_t(iy); }
  std::unordered_set<int64_t> cells_;
  std::unordered_set<int64_t> passable_;
};

}  // namespace macsim::affordances
