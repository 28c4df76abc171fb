// What the KURT's stereo cameras show of the demonstrator: coloured cans standing on the floor
// and the yellow platform of a floor switch, located in base_link by stereo triangulation.
#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "macsim/affordances/kurt_geometry.h"
#include "macsim/client/robot_devices.h"

namespace macsim::affordances {

/// What a sighting looks like.
enum class Kind { Can, Switch };

/// One object seen in a stereo pair.
struct Sighting {
  Kind kind = Kind::Can;
  std::string colour;      ///< "red", "green", "blue", "cyan", "magenta", "yellow"
  double x = 0, y = 0;     ///< m in base_link: the can's axis, the platform's centre
  double range = 0;        ///< m from the left camera
  double width = 0, height = 0;  ///< m, the blob's extent at its range
  cv::Rect box;            ///< in the left image
  double liftable = -1;    ///< a lift model's probability of `liftable` (-1: not judged)
  /// The trials' perception of a can's blob (perception.h): the features of thing_features().
  std::map<std::string, double> features;
};

/// The cans and switch platforms in one stereo pair (pixels of saturated colour, grouped per
/// colour, matched between the eyes along the rows, sized in metres and kept by shape).
std::vector<Sighting> find_objects(const macsim::client::StereoFrame& frame,
                                   const KurtGeometry& geometry);

/// The left image with the sightings drawn on it (for --debug-images).
cv::Mat draw_sightings(const cv::Mat& left, const std::vector<Sighting>& sightings);

}  // namespace macsim::affordances
