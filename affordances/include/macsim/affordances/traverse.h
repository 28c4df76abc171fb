// What stands on the floor in one look of the 3D laser and whether the robot can cross it: the
// returns above the floor grouped into things, each asked of a learned traverse model as a
// traverse trial saw its obstacle (alone, straight ahead, its near side where the trials' stood),
// and the shortest way over a floor plan of 5 cm cells on which the things judged not traversable
// are grown by the robot's half-width and those judged traversable cost a little more than bare
// floor. kurt_navigate and the behaviours' travel stand on it.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "macsim/affordances/model.h"
#include "macsim/affordances/robot_loop.h"
#include "macsim/client/robot_devices.h"

namespace macsim::affordances {

/// A point on the floor plan (odometry frame), m.
using Point2 = std::array<double, 2>;

/// The cells of things, m.
inline constexpr double kGrid = 0.05;
/// The kGrid cell (odometry frame) that holds `p`.
std::pair<int, int> cell_of(const Point2& p);

/// Returns lower than this above the floor are the floor (the trials' corridor), m.
inline constexpr double kAboveFloor = 0.03;
/// Height above the floor of a cloud's point (base_link), m.
double height_above_floor(const std::array<float, 3>& point);

/// The cloud (base_link) in the frame of a way `heading` rad to the left of the robot's: x
/// along the way, y to its left, z unchanged.
macsim::client::Cloud along(const macsim::client::Cloud& cloud, double heading);

/// The traverse features of a way (a cloud turned by along()), computed as a trial computes
/// them of its cloud: the grid ahead, the corridor and the shape of what stands in it.
std::map<std::string, double> way_features(const macsim::client::Cloud& way);

/// The traverse model DIR/traverse.yml, when it takes only what a cloud gives
/// (affordance_learn --features shape or cloud); throws std::runtime_error naming the file and
/// the fault.
AffordanceModel load_traverse_model(const std::string& dir);


/// How high a thing stands: lower than kLowThing everywhere (a joist, a bar), higher, or higher
/// than a traverse trial's view somewhere (a wall: never asked about, never passable).
enum class Height { Low, High, Towering };

/// Something standing on the floor in one cloud: 5 cm cells of returns more than 3 cm above it,
/// less than 15 cm apart (more far away, where the scanner's rings lie further apart), of one
/// Height.
struct Thing {
  std::vector<Point2> cells;        ///< centres of its cells, odometry frame
  std::vector<std::size_t> points;  ///< its returns: indices into the cloud
  Point2 centre{};                  ///< mean of its cells, odometry frame
  double across = 0;                ///< m, the diagonal of its cells' bounding box
  double distance = 0;              ///< m from the robot's middle to its nearest cell
  bool judged = false;              ///< judged at all (else not yet known)
  double p_traversable = 0;         ///< the judgement, [0, 1]
  bool passable = false;            ///< judged traversable (driven into or over)
  Height height = Height::High;
};

/// Things lower than this above the floor (m) are grouped apart from higher ones.
inline constexpr double kLowThing = 0.08;

/// The things of a cloud (base_link) taken at `pose`, up to `range` m away; the robot's own body
/// is left out.
std::vector<Thing> things_in(const macsim::client::Cloud& cloud, const Pose2& pose,
                             double range = 4.0);

/// The cloud without the returns of the things but `kept` (of those with 3 returns or more): what
/// a trial saw of its one obstacle.
macsim::client::Cloud without_others(const macsim::client::Cloud& cloud,
                                     const std::vector<Thing>& things, const Thing& kept);

/// A floor plan between the robot and its goal, and the shortest way across it.
class FloorPlan {
 public:
  /// Cells of `cell` m covering `from` and `to` and `border` m around both.
  FloorPlan(const Point2& from, const Point2& to, double border = 2.5, double cell = 0.05);
  /// A thing on the plan: passable ones cost `passable_cost` times the floor to cross, those not
  /// yet judged `unknown_cost`; the others block every cell within `clearance` m and make those
  /// within `margin` m dearer.
  void add(const Thing& thing, double clearance, double margin, double passable_cost = 2.0,
           double unknown_cost = 3.0);
  /// The cells within `radius` m of `at` block (something it was pressed against).
  void block(const Point2& at, double radius);
  /// The cheapest way from `from` to `to` (8 neighbours; the cells within `escape` m of `from`
  /// may be left even when blocked), as cell centres from `from`; empty when there is none.
  std::vector<Point2> path(double escape = 0.3) const;

 private:
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * columns_ + i; }
  bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < columns_ && j < rows_; }
  int column(double x) const;
  int row(double y) const;
  Point2 centre(int i, int j) const;

  Point2 from_, to_;
  double x0_, y0_, cell_;
  int columns_, rows_;
  std::vector<float> cost_;  // per cell: 1 for bare floor, more for dearer cells
  std::vector<char> blocked_;
};

/// The length (m) of a way of points.
double length(const std::vector<Point2>& way);

/// The traverse trials' obstacle: its near side this far ahead of the robot's middle, m.
inline constexpr double kTrialNear = 0.68;

/// The near side of `thing` of `cloud` (taken at `pose`), m from the robot along the bearing of
/// its middle.
double near_side(const macsim::client::Cloud& cloud, const Pose2& pose, const Thing& thing);

/// P(traversable) the model gives `thing` of `cloud` (taken at `pose`, `things` all of its
/// things) seen alone and straight ahead, as a trial saw its obstacle.
double p_traversable(const AffordanceModel& model, const macsim::client::Cloud& cloud,
                     const Pose2& pose, const std::vector<Thing>& things, const Thing& thing);

}  // namespace macsim::affordances
