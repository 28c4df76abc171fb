// What the KURT's stereo cameras show of the demonstrator: coloured cans and boxes standing on
// the floor and the yellow platform of a floor switch (raised, or flush with the floor), located
// in base_link by stereo triangulation.
#pragma once

#include <map>
#include <optional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "macsim/affordances/kurt_geometry.h"
#include "macsim/client/robot_devices.h"

namespace macsim::affordances {

/// What a sighting looks like.
enum class Kind { Can, Box, Switch };

/// m: a switch plate the cameras see wider than this lies flush with the floor (measured here: a
/// raised platform's yellow top 0.23-0.35 m, a flush plate's 0.49-0.58 m; the height of its
/// middle tells them apart only from close by).
inline constexpr double kFlushPlateWidth = 0.42;

/// One object seen in a stereo pair.
struct Sighting {
  Kind kind = Kind::Can;
  std::string colour;      ///< "red", "green", "blue", "cyan", "magenta", "yellow"
  double x = 0, y = 0;     ///< m in base_link: the can's axis, the box's or the platform's centre
  double range = 0;        ///< m from the left camera
  double width = 0, height = 0;  ///< m, the blob's extent at its range
  double above_floor = 0;  ///< m, the blob's centroid above the floor (a flush switch's is ~0)
  bool on_plate = false;   ///< a box: the switch's yellow shows right below its foot (it stands on the plate)
  cv::Rect box;            ///< in the left image
  double liftable = -1;    ///< a lift model's probability of `liftable` (-1: not judged)
  /// The trials' perception of a can's blob (perception.h): the features of thing_features().
  std::map<std::string, double> features;
};

/// The cans, boxes and switch platforms in one stereo pair (pixels of saturated colour, grouped per
/// colour, matched between the eyes along the rows, sized in metres and kept by shape).
std::vector<Sighting> find_objects(const macsim::client::StereoFrame& frame,
                                   const KurtGeometry& geometry);

/// A plate flush with the floor, judged from its outline: its middle in base_link.
struct FlushPlate {
  double x = 0, y = 0;  ///< m in base_link
  double half_extent = 0;  ///< m: half its extent across the view (its side's half, turned)
};

/// The flush plate in the left image, from the floor points of its yellow (the union of its
/// pieces): half way between its leftmost and rightmost (two opposite corners, or its two sides),
/// which a box standing on its near half leaves in sight. None when no yellow is seen, part of it
/// leaves the image, or its extent is not a plate's.
std::optional<FlushPlate> find_flush_plate(const macsim::client::StereoFrame& frame,
                                           const KurtGeometry& geometry);

/// The left image with the sightings drawn on it (for --debug-images).
cv::Mat draw_sightings(const cv::Mat& left, const std::vector<Sighting>& sightings);

}  // namespace macsim::affordances
