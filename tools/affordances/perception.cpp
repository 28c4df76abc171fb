#include "perception.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace affordances {

namespace {

struct Blob {
  double area = 0, cx = 0, cy = 0;
  cv::Rect box;
  cv::Scalar mean_bgr;
};

/// Saturated, not dark regions of a BGR image, largest first; those touching the border (the
/// robot's own crane at the edge of the view, something half seen) after the others.
std::vector<Blob> blobs(const cv::Mat& bgr) {
  cv::Mat hsv, mask;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  cv::inRange(hsv, cv::Scalar(0, 90, 40), cv::Scalar(180, 255, 255), mask);
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  std::vector<std::pair<bool, Blob>> found;
  for (int i = 1; i < n; ++i) {
    if (stats.at<int>(i, cv::CC_STAT_AREA) < 12) continue;  // a few stray pixels
    Blob b;
    b.area = stats.at<int>(i, cv::CC_STAT_AREA);
    b.cx = centroids.at<double>(i, 0);
    b.cy = centroids.at<double>(i, 1);
    b.box = cv::Rect(stats.at<int>(i, cv::CC_STAT_LEFT), stats.at<int>(i, cv::CC_STAT_TOP),
                     stats.at<int>(i, cv::CC_STAT_WIDTH), stats.at<int>(i, cv::CC_STAT_HEIGHT));
    b.mean_bgr = cv::mean(bgr, labels == i);
    const bool border =
        b.box.x == 0 || b.box.y == 0 || b.box.br().x == bgr.cols || b.box.br().y == bgr.rows;
    found.emplace_back(border, b);
  }
  std::stable_sort(found.begin(), found.end(), [](const auto& x, const auto& y) {
    return x.first != y.first ? !x.first : x.second.area > y.second.area;
  });
  std::vector<Blob> out;
  for (auto& f : found) out.push_back(f.second);
  return out;
}

}  // namespace

void perceive_image(const macsim::client::StereoFrame& frame, Percept& p) {
  if (frame.left.empty() || frame.right.empty() || !(frame.focal > 0)) return;
  const auto in_left = blobs(frame.left);
  if (in_left.empty()) return;
  const Blob* left = &in_left.front();
  p.seen = true;
  p.b = left->mean_bgr[0] / 255.0;
  p.g = left->mean_bgr[1] / 255.0;
  p.r = left->mean_bgr[2] / 255.0;
  cv::Mat pixel(1, 1, CV_8UC3, cv::Scalar(left->mean_bgr[0], left->mean_bgr[1], left->mean_bgr[2]));
  cv::Mat hsv;
  cv::cvtColor(pixel, hsv, cv::COLOR_BGR2HSV_FULL);
  p.hue = hsv.at<cv::Vec3b>(0, 0)[0] * 360.0 / 256.0;
  p.area_px = left->area;
  p.width_px = left->box.width;
  p.height_px = left->box.height;
  p.fill = left->area / (static_cast<double>(left->box.width) * left->box.height);
  p.bearing = std::atan2(frame.cx - left->cx, frame.focal);
  // Its match in the right image: on the same rows, of about its size, left of it.
  const std::vector<Blob> in_right = blobs(frame.right);
  const Blob* right = nullptr;
  double best = 1e9;
  for (const Blob& b : in_right) {
    const double cost =
        std::fabs(b.cy - left->cy) + std::fabs(b.area - left->area) / left->area * 20;
    if (b.cx < left->cx + 1 && cost < best) best = cost, right = &b;
  }
  if (best > 15) right = nullptr;
  const double disparity = right ? left->cx - right->cx : 0.0;
  if (disparity > 0.5 && frame.baseline > 0) {
    p.stereo_range = frame.focal * frame.baseline / disparity;
    p.width_m = p.width_px * p.stereo_range / frame.focal;
  }
}

void perceive_scan(const macsim::client::Laser::Scan& scan, const SensorMount& mount, Percept& p) {
  // The plane of a scanner standing still at angle 0 holds x (ahead) and z; a beam at angle a
  // from straight ahead, range r, hits at x = laser_x + r cos a, z = laser_z + r sin a.
  const double floor_z = -mount.base_height;
  double lowest_z = std::numeric_limits<double>::infinity(), lowest_x = 0;
  double highest_z = -std::numeric_limits<double>::infinity(), highest_x = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < scan.ranges().size(); ++i) {
    const double r = scan.ranges()[i];
    if (!std::isfinite(r) || r < scan.range_min() || r > scan.range_max()) continue;
    const double a = scan.angle_min() + static_cast<double>(i) * scan.angle_increment();
    const double x = mount.laser_x + r * std::cos(a), z = mount.laser_z + r * std::sin(a);
    if (x < 0.3 || x > 3.0) continue;  // the robot itself; too far to matter
    // A beam going down sees the floor at (laser height) / sin: a hit 3 cm shorter is on
    // something (the scanner's noise is about a centimetre).
    const double floor_range = a < 0 ? (mount.laser_z - floor_z) / -std::sin(a) : 1e9;
    if (r > floor_range - 0.03) continue;
    nearest = std::min(nearest, x);
    if (z < lowest_z || (z == lowest_z && x < lowest_x)) lowest_z = z, lowest_x = x;
    if (z > highest_z + 1e-3 || (std::fabs(z - highest_z) <= 1e-3 && x < highest_x))
      highest_z = z, highest_x = x;
  }
  if (!std::isfinite(nearest)) return;
  p.laser_hit = true;
  p.laser_range = nearest;
  p.laser_height = highest_z - floor_z;
  p.laser_depth = highest_x - lowest_x;
  p.laser_slope = std::atan2(highest_z - floor_z, std::max(0.0, highest_x - nearest) + 1e-3);
}

std::vector<double> features(const Percept& p) {
  return {p.r,           p.g,           p.b,
          p.hue,         p.area_px,     p.width_px,
          p.height_px,   p.fill,        p.stereo_range,
          p.width_m,     p.laser_range, p.laser_height,
          p.laser_depth, p.laser_slope};
}

const std::vector<const char*>& feature_names() {
  static const std::vector<const char*> names{"r",           "g",           "b",
                                              "hue",         "area_px",     "width_px",
                                              "height_px",   "fill",        "stereo_range",
                                              "width_m",     "laser_range", "laser_height",
                                              "laser_depth", "laser_slope"};
  return names;
}

}  // namespace affordances
