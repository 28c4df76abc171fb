// What kurt_navigate counts of a run from the 3D laser, besides its things (macsim/affordances/
// traverse.h) and the laser odometry (macsim/affordances/laser_odometry.h): what the laser saw
// along the run, for the summary: things driven through or around.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "macsim/client/robot_devices.h"
#include "macsim/affordances/robot_loop.h"
#include "macsim/affordances/laser_odometry.h"
#include "macsim/affordances/traverse.h"

namespace kurt_navigate {

using macsim::affordances::cell_of;
using macsim::affordances::height_above_floor;
using macsim::affordances::kAboveFloor;
using macsim::affordances::Point2;
using macsim::affordances::align;
using macsim::affordances::static_structure;
using macsim::affordances::StaticMap;

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
