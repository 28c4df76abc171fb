// What the robot perceives of the object (or ramp) before it acts, from its own sensors: colour
// and apparent size from the stereo cameras, range, height and profile from the laser's
// vertical sweep straight ahead, the ground ahead from one turn of the rotating scanner. The one
// perception of the project: the affordance trials write their rows from it, and controllers
// compute the features a learned model (model.h) takes from it. find_package(macsim) ->
// macsim::affordances; depends on the client library and the robot's description only.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "macsim/client/robot_devices.h"
#include "macsim/robot/kurt3d_description.h"

namespace macsim::affordances {

/// The affordances of the seed that a trial can test and a model can be learned for.
enum class Affordance { Lift, Push, Climb, Stack, Traverse };
/// "lift", "push", "climb", "stack", "traverse".
const char* name(Affordance affordance);
/// The affordance of that name, if any.
std::optional<Affordance> affordance_from_name(const std::string& name);

/// The perceived features a learner gets (SI units; pixels where it says so).
struct Percept {
  bool seen = false;           ///< the cameras found a coloured blob
  double r = 0, g = 0, b = 0;  ///< mean colour of the blob, [0, 1]
  double hue = 0;              ///< degrees, [0, 360)
  double area_px = 0;          ///< pixels of the blob in the left image
  double width_px = 0, height_px = 0;
  double fill = 0;          ///< area over its bounding box: 1 for a box face, 0.79 a disc
  double bearing = 0;       ///< rad, counter-clockwise from ahead (left camera)
  double stereo_range = 0;  ///< m along the optical axis, from the blob's disparity
  double width_m = 0;       ///< apparent width at that range, m
  bool laser_hit = false;   ///< the sweep hit something above the floor ahead
  double laser_range = 0;   ///< m ahead of base_link to the nearest hit above the floor
  double laser_height = 0;  ///< m above the floor of the highest hit
  double laser_depth = 0;   ///< m from the lowest to the highest hit, along x
  double laser_slope = 0;   ///< rad, from the lowest to the highest hit (ramps: the slope)
  // Stack: the top of what the sweep hit, and the carried object as the crane found it.
  double top_length = 0;      ///< m along x of the hits within 1 cm of the highest
  double top_flatness = 0;    ///< m, spread (standard deviation) of the hits within 3 cm of the top
  double top_curvature = 0;   ///< 1/m, of a parabola fitted to those hits (a flat top: 0)
  double carried_height = 0;  ///< m, the carried object's top above the floor where it stood
  // Traverse: the 3D cloud of one turn of the rotating scanner, ahead of the robot.
  std::vector<double> grid;     ///< per cell (cell_<row>_<column>_*): nearest, farthest and mean
                                ///< range (m), highest point (m above the floor), slope (rad)
  double free_width = 0;        ///< m between the nearest obstacle points left and right of
                                ///< the robot's axis (above 3 cm, in the grid's reach)
  double corridor_height = 0;   ///< m, the highest point within 0.2 m of the robot's axis
  double corridor_nearest = 0;  ///< m ahead to the nearest such point above 3 cm (0: none)
  // Traverse: the shape of what stands in the grid's reach (its points 3-45 cm above the floor),
  // measured from the thing itself, so that it reads the same from any place the robot stands.
  double shape_height = 0;  ///< m above the floor, of the highest point
  double shape_width = 0;   ///< m across (y), from the rightmost point to the leftmost
  double shape_depth = 0;   ///< m along x, from the nearest point to the farthest
  /// m the top lies behind the front, per 5 cm slice across: from the slice's nearest point to
  /// the nearest of its points within 1 cm of its highest (a ball or a log lying across: its
  /// radius r less sqrt(2 r 1 cm); a box, a post, a log seen end on: 0). The largest slice's and
  /// the median's.
  double shape_recess_max = 0, shape_recess_median = 0;
  double shape_top_depth = 0;  ///< m along x of the points within 1 cm of the highest
};

/// Where the sensors sit on the KURT3D (base_link: x ahead, y left, z up), from its description.
struct SensorMount {
  double base_height = macsim::robot::kurt3d::kBaseHeight;  ///< base_link above the floor, m
  /// The scanner's origin on the rotating unit, m.
  double laser_x = macsim::robot::kurt3d::kRotatingLaser[0],
         laser_z = macsim::robot::kurt3d::kRotatingLaser[2];
};

/// Adds the cameras' view: the largest saturated blob of the left image (of those whose centre
/// lies in `region`, when given), matched in the right.
void perceive_image(const macsim::client::StereoFrame& frame, Percept& percept,
                    const std::optional<cv::Rect>& region = std::nullopt);
/// Adds the laser's: one sweep of the scanner standing still, its plane straight ahead (the
/// top's profile too).
void perceive_scan(const macsim::client::Laser::Scan& scan, const SensorMount& mount,
                   Percept& percept);
/// Adds the 3D cloud's (points in base_link): the grid of cells ahead, the corridor, the shape.
void perceive_cloud(const macsim::client::Cloud& cloud, const SensorMount& mount, Percept& percept);

/// What the robot's sensors gave for one look (each part optional): a stereo pair, a sweep of
/// the scanner standing still, a 3D cloud.
struct SensorInputs {
  std::optional<macsim::client::StereoFrame> frame;
  std::optional<macsim::client::Laser::Scan> scan;
  std::optional<macsim::client::Cloud> cloud;
};

/// The percept of one look: perceive_image (within `region`, if given), perceive_scan and
/// perceive_cloud on what there is.
Percept perceive(const SensorInputs& inputs, const SensorMount& mount = {},
                 const std::optional<cv::Rect>& region = std::nullopt);
/// The boxes of the things perceive_image looks at in an image (saturated, not dark regions),
/// largest first: the `region` a controller gives it to perceive each thing in view.
std::vector<cv::Rect> objects_in_view(const cv::Mat& bgr);
/// Writes a look to DIR/NAME_left.png and NAME_right.png (lossless) and DIR/NAME.yml.gz (the
/// calibration, the sweep, the cloud: every number as it came). Throws std::runtime_error.
void save_inputs(const SensorInputs& inputs, const std::string& dir, const std::string& name);
/// Reads a look save_inputs wrote; throws std::runtime_error naming the file and the fault.
SensorInputs load_inputs(const std::string& dir, const std::string& name);

/// The grid's cells ahead of the robot: rows along x, columns along y (m, base_link).
struct GroundGrid {
  static constexpr int kRows = 8, kColumns = 6, kValues = 5;
  static constexpr double kNear = 0.25, kRowDepth = 0.2;  ///< x of the first row, m
  static constexpr double kWidth = 0.9;                   ///< y from -kWidth/2, m
  static constexpr double kTop = 0.45;  ///< points higher above the floor are left out, m
};

/// The features a learner trains on for an affordance, in a fixed order, and their names:
/// every affordance has the camera and laser-sweep features; stack adds the top's profile and
/// the carried height, traverse the cloud's grid, corridor and shape.
std::vector<double> features(const Percept& percept, Affordance affordance = Affordance::Lift);
const std::vector<std::string>& feature_names(Affordance affordance = Affordance::Lift);
/// The features of one sensor, by group name: "camera" (the blob in the stereo pair), "sweep"
/// (the laser's sweep ahead), "top" (stack: the top's profile, the carried height), "cloud"
/// (traverse: the grid, cells at fixed places ahead) or "shape" (traverse: the corridor and
/// what stands in it, measured from itself: the same from any stance); nullptr for another name.
const std::vector<std::string>* feature_group(const std::string& name);
/// The same features by name (what AffordanceModel::predict takes).
std::map<std::string, double> named_features(const Percept& percept, Affordance affordance);

}  // namespace macsim::affordances
