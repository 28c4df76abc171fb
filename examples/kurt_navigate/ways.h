// What kurt_navigate takes from one 3D laser cloud besides its things (macsim/affordances/
// traverse.h): what stands still and the laser odometry that aligns each look to it, and what the
// laser saw along the run, for the summary: things driven through or around.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "macsim/client/robot_devices.h"
#include "macsim/affordances/robot_loop.h"
#include "macsim/affordances/traverse.h"

namespace kurt_navigate {

using macsim::affordances::cell_of;
using macsim::affordances::height_above_floor;
using macsim::affordances::kAboveFloor;
using macsim::affordances::Point2;

/// What stands still in a cloud taken at `pose`: its returns kStaticHeight-60 cm above the floor
/// (higher than anything the robot may push aside or drive over), 0.6-9.5 m away, in the
/// odometry frame, one per 5 cm cell.
std::vector<Point2> static_structure(const macsim::client::Cloud& cloud,
                                     const macsim::affordances::Pose2& pose);
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

/// Things above the floor the laser saw during a run (cells of 10 cm in the odometry frame,
/// grouped into things), and the path the robot took: which things it drove through (its
/// footprint crossed where they stood) and which around (passed within 1 m, not touching).
class Sightings {
 public:
  /// Adds a cloud taken at `pose` (points up to 3 m away, 3-45 cm above the floor).
  void add(const macsim::client::Cloud& cloud, const macsim::affordances::Pose2& pose);
  /// Adds where the robot's middle was.
  void pass(const macsim::affordances::Pose2& pose);
  struct Counts {
    int through = 0, around = 0, seen = 0;
  };
  /// Things of at most 1.2 m across (walls are not counted), judged against the path.
  Counts count(double half_width) const;

 private:
  std::map<std::pair<int, int>, int> cells_;
  std::vector<std::pair<double, double>> path_;
};

}  // namespace kurt_navigate
