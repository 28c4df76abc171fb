#include "macsim/affordances/vision.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

namespace macsim::affordances {

namespace {

constexpr int kMinSaturation = 110;  // of a colour the cameras tell

/// A hue band of OpenCV's HSV (hue 0..179); red wraps around 0.
struct ColourClass {
  const char* name;
  int lo, hi;
  int lo2 = -1, hi2 = -1;
  int min_saturation = kMinSaturation;
};
/// Red wants more saturation than the rest: the walls' bricks are red too, at 160-191 (measured
/// on the cameras' pictures; a red can's or box's faces, lit or shaded, are above 224), and a
/// box before a wall would be one blob with it.
constexpr std::array<ColourClass, 6> kColours{{{"red", 0, 7, 165, 179, 200},
                                               {"yellow", 18, 34},
                                               {"green", 40, 80},
                                               {"cyan", 85, 100},
                                               {"blue", 101, 130},
                                               {"magenta", 140, 164}}};
constexpr int kMinValue = 50, kMinArea = 12;
constexpr double kCanRadius = 0.033;
constexpr double kBoxHalf = 0.1;  // m: half a pushable box's side (the demonstrator's are 0.2 m)
constexpr double kOneBoxWidest = 0.4;  // m: one box seen from any side is at most this wide

struct ColourBlob {
  int colour = 0;
  cv::Rect box;
  double cx = 0, cy = 0;
  int area = 0;
  bool dark_below = false;  // stands on something dark (a switch's base), not on the floor
};

/// Whether most columns of component `label` have dark, grey pixels right below their lowest
/// pixel of it: a switch's dark base shows below its platform, the floor below anything else.
bool dark_below(const cv::Mat& labels, int label, const cv::Rect& box, const cv::Mat& saturation,
                const cv::Mat& value) {
  int columns = 0, dark = 0;
  for (int x = box.x + box.width / 4; x < box.x + box.width - box.width / 4; ++x) {
    int lowest = -1;
    for (int y = box.y + box.height - 1; y >= box.y; --y) {
      if (labels.at<int>(y, x) == label) {
        lowest = y;
        break;
      }
    }
    if (lowest < 0 || lowest + 3 >= labels.rows) continue;
    ++columns;
    int dark_pixels = 0;
    for (int y = lowest + 1; y <= lowest + 3; ++y) {
      if (value.at<uint8_t>(y, x) < 100 && saturation.at<uint8_t>(y, x) < 90) ++dark_pixels;
    }
    dark += dark_pixels >= 2 ? 1 : 0;
  }
  return columns > 0 && dark * 2 >= columns;
}

std::vector<ColourBlob> find_blobs(const cv::Mat& bgr) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  std::vector<cv::Mat> channel;
  cv::split(hsv, channel);
  const cv::Mat bright = channel[2] >= kMinValue;
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  std::vector<ColourBlob> blobs;
  for (int c = 0; c < static_cast<int>(kColours.size()); ++c) {
    const ColourClass& colour = kColours[c];
    cv::Mat mask = (channel[0] >= colour.lo) & (channel[0] <= colour.hi);
    if (colour.lo2 >= 0) mask |= (channel[0] >= colour.lo2) & (channel[0] <= colour.hi2);
    mask &= bright & (channel[1] >= colour.min_saturation);
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, kernel);  // textures' stripes, edges
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
    for (int i = 1; i < n; ++i) {
      const int area = stats.at<int>(i, cv::CC_STAT_AREA);
      if (area < kMinArea) continue;
      const cv::Rect box(stats.at<int>(i, cv::CC_STAT_LEFT), stats.at<int>(i, cv::CC_STAT_TOP),
                         stats.at<int>(i, cv::CC_STAT_WIDTH), stats.at<int>(i, cv::CC_STAT_HEIGHT));
      const bool switch_colour = std::string(colour.name) == "yellow";
      blobs.push_back({c, box, centroids.at<double>(i, 0), centroids.at<double>(i, 1), area,
                       switch_colour && dark_below(labels, i, box, channel[1], channel[2])});
    }
  }
  return blobs;
}

/// The right eye's blob that is the left one's: same colour, same rows, a similar size, in
/// front of the cameras; the closest such by rows and size.
std::optional<ColourBlob> match(const ColourBlob& left, const std::vector<ColourBlob>& right) {
  std::optional<ColourBlob> best;
  double best_cost = 1e9;
  for (const ColourBlob& r : right) {
    if (r.colour != left.colour) continue;
    const double rows = std::fabs(r.cy - left.cy);
    const double size = static_cast<double>(r.area) / left.area;
    if (rows > std::max(2.5, 0.2 * left.box.height) || size < 0.6 || size > 1.6) continue;
    if (left.cx - r.cx < 0.5) continue;
    const double cost = rows + 5.0 * std::fabs(1.0 - size);
    if (cost < best_cost) {
      best_cost = cost;
      best = r;
    }
  }
  return best;
}

bool touches_border(const cv::Rect& box, const cv::Size& size) {
  return box.x <= 0 || box.y <= 0 || box.x + box.width >= size.width ||
         box.y + box.height >= size.height;
}

/// Whether most of the pixels in the few rows below `box`'s middle half are the switch's yellow:
/// a thing whose foot the plate shows in front of stands on it.
bool yellow_below(const cv::Mat& bgr, const cv::Rect& box) {
  const int top = box.y + box.height + 1, rows = 5;
  const int from = box.x + box.width / 4, to = box.x + box.width - box.width / 4;
  if (top + rows > bgr.rows || to <= from) return false;
  cv::Mat hsv;
  cv::cvtColor(bgr(cv::Rect(from, top, to - from, rows)), hsv, cv::COLOR_BGR2HSV);
  const ColourClass& yellow = kColours[1];
  int count = 0;
  for (int y = 0; y < hsv.rows; ++y)
    for (int x = 0; x < hsv.cols; ++x) {
      const auto& p = hsv.at<cv::Vec3b>(y, x);
      count += p[0] >= yellow.lo && p[0] <= yellow.hi && p[1] >= yellow.min_saturation && p[2] >= kMinValue;
    }
  return 2 * count >= hsv.rows * hsv.cols;
}

}  // namespace

std::vector<Sighting> find_objects(const macsim::client::StereoFrame& frame,
                                   const KurtGeometry& g) {
  const std::vector<ColourBlob> left = find_blobs(frame.left);
  const std::vector<ColourBlob> right = find_blobs(frame.right);
  const double f = frame.focal, cp = std::cos(g.camera_pitch), sp = std::sin(g.camera_pitch);
  std::vector<Sighting> out;
  for (const ColourBlob& l : left) {
    if (touches_border(l.box, frame.left.size())) continue;  // part of it is out of sight
    const auto r = match(l, right);
    if (!r) continue;
    // Triangulate the centroid: optical frame (x right, y down, z ahead), then the camera's
    // frame (x ahead, y left, z up), pitched down, then base_link.
    const double z = f * frame.baseline / (l.cx - r->cx);
    const double ox = (l.cx - frame.cx) * z / f, oy = (l.cy - frame.cy) * z / f;
    const double ahead = z, left_of = -ox, up = -oy;
    const double bx = g.camera_x + cp * ahead + sp * up;
    const double by = g.camera_y + left_of;
    const double height = g.camera_z + g.base_height - sp * ahead + cp * up;  // above the floor
    Sighting s;
    s.colour = kColours[l.colour].name;
    s.range = std::sqrt(z * z + ox * ox + oy * oy);
    s.width = l.box.width * z / f;
    s.height = l.box.height * z / f;
    s.box = l.box;
    const double fill = static_cast<double>(l.area) / l.box.area();
    s.above_floor = height;
    // The centroid lies on the near side of an upright thing: its middle is further on.
    const double dx = bx - g.camera_x, dy = by - g.camera_y, d = std::hypot(dx, dy);
    if (s.colour == std::string("yellow")) {
      // A switch platform: a flat, wide, solid yellow slab on a dark base just above the floor,
      // or a plate flush with it (its thin rim hardly shows; seen from close by, its square is
      // less flat than a raised platform's).
      const bool flush = s.width > kFlushPlateWidth;
      if (s.width < 0.12 || s.width > (flush ? 0.7 : 0.5) || s.height > 0.25 ||
          l.box.width < (flush ? 1.0 : 1.5) * l.box.height ||
          fill < 0.45 || height < -0.02 || height > 0.15 || !(l.dark_below || flush)) {
        continue;
      }
      s.kind = Kind::Switch;
      s.x = bx;
      s.y = by;
    } else if (s.width >= 0.18 && s.width <= 2 * kOneBoxWidest && s.height >= 0.15 && s.height <= 0.4 &&
               fill >= 0.6 && height >= 0.04 && height <= 0.2) {
      // A box to push (measured here: a 0.2 m box 0.22-0.29 m wide, 0.26-0.31 m high with its top;
      // a 0.1 m cube 0.15 m wide): a solid face, its top seen with it from close by, on the floor.
      s.kind = Kind::Box;
      s.x = bx + kBoxHalf * dx / d;
      s.y = by + kBoxHalf * dy / d;
      s.on_plate = yellow_below(frame.left, l.box);
      if (s.width > kOneBoxWidest) {
        // Wider than one box: two of a colour side by side (a pushed box came to rest against the
        // other), one in each half of the blob, at the blob's depth.
        for (const double quarter : {0.25, 0.75}) {
          Sighting half = s;
          // The centroid's triangulation, moved sideways to the quarter's column.
          const double hy = by - (l.box.x + quarter * l.box.width - l.cx) * z / f;
          const double hd = std::hypot(dx, hy - g.camera_y);
          half.width = s.width / 2;
          half.x = bx + kBoxHalf * dx / hd;
          half.y = hy + kBoxHalf * (hy - g.camera_y) / hd;
          out.push_back(half);
        }
        continue;
      }
    } else {
      // A can: an upright cylinder's side, taller than wide, standing on the floor.
      if (s.width < 0.035 || s.width > 0.11 || s.height < 0.06 || s.height > 0.22 ||
          l.box.height < 1.1 * l.box.width || height < 0.02 || height > 0.14) {
        continue;
      }
      s.kind = Kind::Can;
      s.x = bx + kCanRadius * dx / d;
      s.y = by + kCanRadius * dy / d;
    }
    out.push_back(s);
  }
  return out;
}

std::optional<FlushPlate> find_flush_plate(const macsim::client::StereoFrame& frame,
                                           const KurtGeometry& g) {
  constexpr double kPlateTop = 0.0055;            // m: the yellow top above the floor
  constexpr double kLeast = 0.17, kMost = 0.31;   // m: half extents a 0.4 m square top shows (0.2-0.28)
  const cv::Mat& bgr = frame.left;
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  const ColourClass& yellow = kColours[1];
  cv::Mat mask;
  cv::inRange(hsv, cv::Scalar(yellow.lo, yellow.min_saturation, kMinValue), cv::Scalar(yellow.hi, 255, 255), mask);
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, {2, 2}));
  std::vector<cv::Point> pixels;
  cv::findNonZero(mask, pixels);
  if (pixels.size() < static_cast<std::size_t>(kMinArea) || frame.focal <= 0) return std::nullopt;
  const cv::Rect around = cv::boundingRect(pixels);
  if (around.x <= 0 || around.y <= 0 || around.x + around.width >= bgr.cols ||
      around.y + around.height >= bgr.rows)
    return std::nullopt;  // part of it out of sight
  const double f = frame.focal, cp = std::cos(g.camera_pitch), sp = std::sin(g.camera_pitch);
  const double above = g.camera_z + g.base_height - kPlateTop;
  struct FloorPoint {
    double x, y;
  };
  std::vector<FloorPoint> floor;
  floor.reserve(pixels.size());
  for (const cv::Point& p : pixels) {
    // The pixel's ray (camera frame: x ahead, y left, z up, per metre ahead), pitched down, to
    // where it meets the plate's plane.
    const double left_of = -(p.x - frame.cx) / f, up = -(p.y - frame.cy) / f;
    const double down = sp - cp * up;  // the ray's fall per metre ahead
    if (down <= 1e-3) return std::nullopt;  // at or above the horizon: not on the floor
    const double t = above / down;
    floor.push_back({g.camera_x + t * (cp + sp * up), g.camera_y + t * left_of});
  }
  const auto [least, most] =
      std::minmax_element(floor.begin(), floor.end(),
                          [](const FloorPoint& a, const FloorPoint& b) { return a.y < b.y; });
  const double least_y = least->y, most_y = most->y, half = (most_y - least_y) / 2;
  if (half < kLeast || half > kMost) return std::nullopt;
  // The leftmost and rightmost of a square are two opposite corners (or, square to the view, its
  // two sides): its middle lies half way between them, however much of its near or far part a
  // box hides.
  constexpr double kEdge = 0.02;  // m: the points within this of the extreme are the corner or side
  double left_x = 0, right_x = 0;
  int left_n = 0, right_n = 0;
  for (const FloorPoint& p : floor) {
    if (p.y >= most_y - kEdge) left_x += p.x, ++left_n;
    if (p.y <= least_y + kEdge) right_x += p.x, ++right_n;
  }
  return FlushPlate{(left_x / left_n + right_x / right_n) / 2, (least_y + most_y) / 2, half};
}

cv::Mat draw_sightings(const cv::Mat& left, const std::vector<Sighting>& sightings) {
  cv::Mat out = left.clone();
  for (const Sighting& s : sightings) {
    cv::rectangle(out, s.box, s.kind == Kind::Switch ? cv::Scalar(0, 0, 0) : cv::Scalar(255, 255, 255));
    char text[64];
    std::snprintf(text, sizeof text, "%s%s %.2f,%.2f", s.kind == Kind::Switch ? "switch" : s.colour.c_str(),
                  s.kind == Kind::Box ? " box" : "", s.x, s.y);
    cv::putText(out, text, {s.box.x, std::max(8, s.box.y - 2)}, cv::FONT_HERSHEY_PLAIN, 0.7,
                cv::Scalar(255, 255, 255));
  }
  return out;
}

}  // namespace macsim::affordances
