// Laser odometry: where the robot stands by what stands still around it (walls, posts: the 3D
// laser's returns higher than anything it pushes or drives over), laid onto what it saw before.
// Wheel odometry counts a track that slips against something it cannot pass as distance; this
// does not.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "macsim/affordances/robot_loop.h"
#include "macsim/affordances/traverse.h"
#include "macsim/client/robot_devices.h"

namespace macsim::affordances {

/// What stands still in a cloud taken at `pose`: its returns kStaticHeight-60 cm above the floor
/// (higher than anything the robot may push aside or drive over), 0.6-9.5 m away, in the
/// odometry frame, one per 5 cm cell.
std::vector<Point2> static_structure(const macsim::client::Cloud& cloud,
                                     const Pose2& pose);
/// Returns this high above the floor or higher belong to what stands still, m.
inline constexpr double kStaticHeight = 0.25;

/// Laser odometry: the shift (dx, dy) that lays `now` onto `map` (both from static_structure();
/// the heading comes from the IMU), by ICP (point to line where the points make a line, else
/// point to point); nullopt when fewer than 30 points match or the structure seen leaves the
/// shift undetermined. The fit starts from no shift and from each of `guesses` (e.g. "its tracks
/// slipped by half the stretch"); a guess's fit is taken when it lays the points clearly better
/// than the wheels'. When no start fits, starts up to kSearch m around are tried. Wheel odometry
/// counts a track that slips against something it cannot pass as distance; this does not.
std::optional<std::array<double, 2>> align(const std::vector<Point2>& map,
                                           const std::vector<Point2>& now,
                                           const std::vector<std::array<double, 2>>& guesses = {});

/// How far from the wheels' word align() looks for a fit when none fits near it, m.
inline constexpr double kSearch = 1.2;

/// The static structure seen so far (odometry frame, one point per 5 cm cell, where it was first
/// seen): what each look is aligned to, so that errors do not add up from look to look.
class StaticMap {
 public:
  /// Adds the points of a look (aligned already).
  void add(const std::vector<Point2>& points);
  const std::vector<Point2>& points() const { return points_; }

 private:
  std::map<std::pair<int, int>, std::size_t> cells_;
  std::vector<Point2> points_;
};

}  // namespace macsim::affordances
