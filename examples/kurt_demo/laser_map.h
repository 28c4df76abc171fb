// What the KURT's 3D laser cloud shows of the demonstrator: the tall wall that splits the room,
// the passage a door leaves open in it, and whether a straight way is free.
#pragma once

#include <optional>
#include <vector>

#include "kurt_geometry.h"
#include "macsim/client/robot_devices.h"

namespace kurt_demo {

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

}  // namespace kurt_demo
