#include "macsim/affordances/perception.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "macsim/affordances/traverse.h"
#include "macsim/images/image_files.h"

namespace macsim::affordances {

namespace {

struct SaturatedBlob {
  double area = 0, cx = 0, cy = 0;
  cv::Rect box;
  cv::Scalar mean_bgr;
};

/// Saturated, not dark regions of a BGR image, largest first; those touching the border (the
/// robot's own crane at the edge of the view, something half seen) after the others.
std::vector<SaturatedBlob> blobs(const cv::Mat& bgr) {
  cv::Mat hsv, mask;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  cv::inRange(hsv, cv::Scalar(0, 90, 40), cv::Scalar(180, 255, 255), mask);
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  std::vector<std::pair<bool, SaturatedBlob>> found;
  for (int i = 1; i < n; ++i) {
    if (stats.at<int>(i, cv::CC_STAT_AREA) < 12) continue;  // a few stray pixels
    SaturatedBlob b;
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
  std::vector<SaturatedBlob> out;
  for (auto& f : found) out.push_back(f.second);
  return out;
}

}  // namespace

const char* name(Affordance a) {
  switch (a) {
    case Affordance::Lift:
      return "lift";
    case Affordance::Push:
      return "push";
    case Affordance::Climb:
      return "climb";
    case Affordance::Stack:
      return "stack";
    default:
      return "traverse";
  }
}

std::optional<Affordance> affordance_from_name(const std::string& n) {
  for (auto a : {Affordance::Lift, Affordance::Push, Affordance::Climb, Affordance::Stack,
                 Affordance::Traverse}) {
    if (n == name(a)) return a;
  }
  return std::nullopt;
}

void perceive_image(const macsim::client::StereoFrame& frame, Percept& p,
                    const std::optional<cv::Rect>& region) {
  if (frame.left.empty() || frame.right.empty() || !(frame.focal > 0)) return;
  auto in_left = blobs(frame.left);
  if (region) {
    std::erase_if(in_left, [&](const SaturatedBlob& b) {
      return !region->contains(cv::Point(static_cast<int>(b.cx), static_cast<int>(b.cy)));
    });
  }
  if (in_left.empty()) return;
  const SaturatedBlob* left = &in_left.front();
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
  const std::vector<SaturatedBlob> in_right = blobs(frame.right);
  const SaturatedBlob* right = nullptr;
  double best = 1e9;
  for (const SaturatedBlob& b : in_right) {
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
  std::vector<cv::Point2d> hits;  // (x, z) of the beams that hit something above the floor
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
    hits.emplace_back(x, z);
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
  // The top: the hits within 3 cm of the highest, without a vertical face in front of it (hits
  // stacked within 1 cm of the front-most x over more than 1 cm of height), as a parabola
  // z = a + b x + c x^2 (x from their middle); its length from those within 1 cm.
  std::vector<cv::Point2d> top;
  double front = 1e9;
  for (const auto& hit : hits) {
    if (hit.y < highest_z - 0.03) continue;
    top.push_back(hit);
    front = std::min(front, hit.x);
  }
  double face_lo = 1e9, face_hi = -1e9;
  for (const auto& t : top) {
    if (t.x < front + 0.01) face_lo = std::min(face_lo, t.y), face_hi = std::max(face_hi, t.y);
  }
  if (face_hi - face_lo > 0.01 && top.size() > 3) {
    std::vector<cv::Point2d> above;
    for (const auto& t : top) {
      if (t.x >= front + 0.01 || t.y >= highest_z - 0.002) above.push_back(t);
    }
    top.swap(above);
  }
  double top_lo = 1e9, top_hi = -1e9;
  for (const auto& t : top) {
    if (t.y >= highest_z - 0.01) top_lo = std::min(top_lo, t.x), top_hi = std::max(top_hi, t.x);
  }
  p.top_length = top_hi - top_lo;
  double mean_x = 0, mean_z = 0;
  for (const auto& t : top) mean_x += t.x, mean_z += t.y;
  mean_x /= static_cast<double>(top.size());
  mean_z /= static_cast<double>(top.size());
  double spread = 0;
  for (const auto& t : top) spread += (t.y - mean_z) * (t.y - mean_z);
  p.top_flatness = std::sqrt(spread / static_cast<double>(top.size()));
  // A parabola needs three hits spread over 3 cm at least (beams a degree apart may put two
  // within millimetres: their curvature would be noise); kept within +-100 1/m (a 1 cm radius).
  double span_lo = 1e9, span_hi = -1e9;
  for (const auto& t : top) span_lo = std::min(span_lo, t.x), span_hi = std::max(span_hi, t.x);
  if (top.size() >= 3 && span_hi - span_lo >= 0.03) {
    cv::Mat a(static_cast<int>(top.size()), 3, CV_64F), b(static_cast<int>(top.size()), 1, CV_64F);
    for (int i = 0; i < a.rows; ++i) {
      const double x = top[static_cast<std::size_t>(i)].x - mean_x;
      a.at<double>(i, 0) = 1;
      a.at<double>(i, 1) = x;
      a.at<double>(i, 2) = x * x;
      b.at<double>(i, 0) = top[static_cast<std::size_t>(i)].y;
    }
    cv::Mat c;
    if (cv::solve(a, b, c, cv::DECOMP_SVD))
      p.top_curvature = std::clamp(2 * c.at<double>(2, 0), -100.0, 100.0);
  }
}

namespace {

/// The shape features of the points (x, y, height above the floor) that stand in the grid's reach.
void perceive_shape(const std::vector<std::array<double, 3>>& standing, Percept& p) {
  constexpr double kSlice = 0.05, kTopBand = 0.01;
  struct Slice {
    double nearest = 1e9, highest = 0;
    std::vector<std::array<double, 2>> points;  // x, height
  };
  std::map<int, Slice> slices;
  double near = 1e9, far = -1e9, left = -1e9, right = 1e9, highest = 0;
  for (const auto& [x, y, h] : standing) {
    near = std::min(near, x), far = std::max(far, x);
    right = std::min(right, y), left = std::max(left, y);
    highest = std::max(highest, h);
    Slice& s = slices[static_cast<int>(std::floor(y / kSlice))];
    s.nearest = std::min(s.nearest, x);
    s.highest = std::max(s.highest, h);
    s.points.push_back({x, h});
  }
  p.shape_height = p.shape_width = p.shape_depth = 0;
  p.shape_recess_max = p.shape_recess_median = p.shape_top_depth = 0;
  if (standing.empty()) return;
  p.shape_height = highest;
  p.shape_width = left - right;
  p.shape_depth = far - near;
  double top_near = 1e9, top_far = -1e9;
  for (const auto& [x, y, h] : standing) {
    if (h < highest - kTopBand) continue;
    top_near = std::min(top_near, x), top_far = std::max(top_far, x);
  }
  p.shape_top_depth = top_far - top_near;
  std::vector<double> recesses;
  for (const auto& [key, s] : slices) {
    if (s.points.size() < 3) continue;  // a stray return
    double top = 1e9;
    for (const auto& [x, h] : s.points) {
      if (h >= s.highest - kTopBand) top = std::min(top, x);
    }
    recesses.push_back(top - s.nearest);
  }
  if (recesses.empty()) return;
  std::sort(recesses.begin(), recesses.end());
  p.shape_recess_max = recesses.back();
  p.shape_recess_median = recesses[recesses.size() / 2];
}

}  // namespace

void perceive_cloud(const macsim::client::Cloud& cloud, const SensorMount& mount, Percept& p) {
  using G = GroundGrid;
  struct Cell {
    double nearest = 1e9, farthest = 0, sum = 0, highest = 0;
    int n = 0;
    // sums for the plane z = a x + b y + c
    double sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0;
  };
  std::array<Cell, G::kRows * G::kColumns> cells;
  const double floor_z = -mount.base_height;
  double left = G::kWidth / 2, right = -G::kWidth / 2;
  p.corridor_height = 0;
  p.corridor_nearest = 0;
  std::vector<std::array<double, 3>> standing;  // x, y, height of the returns above the floor
  for (const auto& q : cloud.points) {
    const double x = q[0], y = q[1], h = q[2] - floor_z;
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(h)) continue;
    const int row = static_cast<int>(std::floor((x - G::kNear) / G::kRowDepth));
    const int column =
        static_cast<int>(std::floor((y + G::kWidth / 2) / (G::kWidth / G::kColumns)));
    if (row < 0 || row >= G::kRows || column < 0 || column >= G::kColumns || h > G::kTop) continue;
    const double range = std::hypot(x - mount.laser_x, y, q[2] - mount.laser_z);
    Cell& c = cells[static_cast<std::size_t>(row * G::kColumns + column)];
    c.nearest = std::min(c.nearest, range);
    c.farthest = std::max(c.farthest, range);
    c.sum += range;
    c.highest = std::max(c.highest, h);
    ++c.n;
    c.sx += x, c.sy += y, c.sz += h;
    c.sxx += x * x, c.sxy += x * y, c.syy += y * y, c.sxz += x * h, c.syz += y * h;
    if (h > kAboveFloor) {
      standing.push_back({x, y, h});
      if (y >= 0) left = std::min(left, y);
      if (y < 0) right = std::max(right, y);
    }
    if (std::fabs(y) < 0.2) {
      p.corridor_height = std::max(p.corridor_height, h);
      if (h > kAboveFloor && (p.corridor_nearest == 0 || x < p.corridor_nearest))
        p.corridor_nearest = x;
    }
  }
  p.free_width = left - right;
  perceive_shape(standing, p);
  p.grid.assign(cells.size() * G::kValues, 0.0);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Cell& c = cells[i];
    if (c.n == 0) continue;
    double* v = &p.grid[i * G::kValues];
    v[0] = c.nearest;
    v[1] = c.farthest;
    v[2] = c.sum / c.n;
    v[3] = c.highest;
    if (c.n >= 3) {  // least squares: the plane's gradient (a, b), its slope atan |(a, b)|
      const cv::Matx33d m(c.sxx, c.sxy, c.sx, c.sxy, c.syy, c.sy, c.sx, c.sy, c.n);
      const cv::Vec3d r(c.sxz, c.syz, c.sz);
      cv::Vec3d plane;
      if (cv::solve(m, r, plane, cv::DECOMP_SVD)) v[4] = std::atan(std::hypot(plane[0], plane[1]));
    }
  }
}

namespace {

/// The grid's feature names: cell_<row>_<column>_<value>.
std::vector<std::string> grid_names() {
  static const char* kValues[GroundGrid::kValues] = {"near", "far", "mean", "high", "slope"};
  std::vector<std::string> names;
  for (int r = 0; r < GroundGrid::kRows; ++r)
    for (int c = 0; c < GroundGrid::kColumns; ++c)
      for (const char* v : kValues)
        names.push_back("cell_" + std::to_string(r) + "_" + std::to_string(c) + "_" + v);
  return names;
}

}  // namespace

std::vector<double> features(const Percept& p, Affordance affordance) {
  std::vector<double> f{p.r,           p.g,           p.b,
                        p.hue,         p.area_px,     p.width_px,
                        p.height_px,   p.fill,        p.stereo_range,
                        p.width_m,     p.laser_range, p.laser_height,
                        p.laser_depth, p.laser_slope};
  if (affordance == Affordance::Stack) {
    f.insert(f.end(), {p.top_length, p.top_flatness, p.top_curvature, p.carried_height});
  } else if (affordance == Affordance::Traverse) {
    std::vector<double> grid = p.grid;
    grid.resize(
        static_cast<std::size_t>(GroundGrid::kRows * GroundGrid::kColumns * GroundGrid::kValues),
        0.0);
    f.insert(f.end(), grid.begin(), grid.end());
    f.insert(f.end(), {p.free_width, p.corridor_height, p.corridor_nearest});
    f.insert(f.end(), {p.shape_height, p.shape_width, p.shape_depth, p.shape_recess_max,
                       p.shape_recess_median, p.shape_top_depth});
  }
  return f;
}

std::vector<cv::Rect> objects_in_view(const cv::Mat& bgr) {
  std::vector<cv::Rect> boxes;
  if (bgr.empty()) return boxes;
  for (const SaturatedBlob& b : blobs(bgr)) boxes.push_back(b.box);
  return boxes;
}

Percept perceive(const SensorInputs& in, const SensorMount& mount,
                 const std::optional<cv::Rect>& region) {
  Percept p;
  if (in.frame) perceive_image(*in.frame, p, region);
  if (in.scan) perceive_scan(*in.scan, mount, p);
  if (in.cloud) perceive_cloud(*in.cloud, mount, p);
  return p;
}

void save_inputs(const SensorInputs& in, const std::string& dir, const std::string& name) {
  std::filesystem::create_directories(dir);
  const std::string base = dir + "/" + name;
  cv::FileStorage fs(base + ".yml.gz", cv::FileStorage::WRITE);
  if (!fs.isOpened()) throw std::runtime_error(base + ".yml.gz: cannot be written");
  if (in.frame) {
    for (const auto& [side, image] : {std::pair{"left", &in.frame->left},
                                      std::pair{"right", &in.frame->right}}) {
      const std::string file = base + "_" + side + ".png";
      if (!images::write_image(file, *image)) throw std::runtime_error(file + ": cannot be written");
    }
    fs << "frame" << "{" << "stamp" << in.frame->stamp << "focal" << in.frame->focal << "cx"
       << in.frame->cx << "cy" << in.frame->cy << "baseline" << in.frame->baseline << "}";
  }
  if (in.scan) {
    const auto& sc = *in.scan;
    fs << "scan" << "{" << "stamp_sec" << sc.header().stamp().sec() << "stamp_nanosec"
       << static_cast<int>(sc.header().stamp().nanosec()) << "frame_id" << sc.header().frame_id()
       << "angle_min" << sc.angle_min() << "angle_max" << sc.angle_max() << "angle_increment"
       << sc.angle_increment() << "range_min" << sc.range_min() << "range_max" << sc.range_max()
       << "ranges" << sc.ranges() << "}";
  }
  if (in.cloud) {
    cv::Mat points(static_cast<int>(in.cloud->points.size()), 3, CV_32F);
    for (int i = 0; i < points.rows; ++i)
      for (int k = 0; k < 3; ++k)
        points.at<float>(i, k) = in.cloud->points[static_cast<std::size_t>(i)][k];
    fs << "cloud" << "{" << "stamp" << in.cloud->stamp << "points" << points << "}";
  }
}

SensorInputs load_inputs(const std::string& dir, const std::string& name) {
  const std::string base = dir + "/" + name;
  const std::string file = base + ".yml.gz";
  SensorInputs in;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw std::runtime_error(file + ": no such file");
  try {
    cv::FileStorage fs(file, cv::FileStorage::READ);
    if (!fs.isOpened()) throw std::runtime_error(file + ": no such file");
    if (const auto f = fs["frame"]; !f.empty()) {
      macsim::client::StereoFrame frame;
      f["stamp"] >> frame.stamp;
      f["focal"] >> frame.focal;
      f["cx"] >> frame.cx;
      f["cy"] >> frame.cy;
      f["baseline"] >> frame.baseline;
      frame.left = images::read_image(base + "_left.png");
      frame.right = images::read_image(base + "_right.png");
      if (frame.left.empty() || frame.right.empty())
        throw std::runtime_error(base + "_left.png or _right.png: missing or not an image");
      in.frame = frame;
    }
    if (const auto f = fs["scan"]; !f.empty()) {
      macsim::client::Laser::Scan scan;
      int sec = 0, nanosec = 0;
      float value = 0;
      f["stamp_sec"] >> sec;
      f["stamp_nanosec"] >> nanosec;
      scan.header().stamp().sec(sec);
      scan.header().stamp().nanosec(static_cast<uint32_t>(nanosec));
      scan.header().frame_id(static_cast<std::string>(f["frame_id"]));
      f["angle_min"] >> value, scan.angle_min(value);
      f["angle_max"] >> value, scan.angle_max(value);
      f["angle_increment"] >> value, scan.angle_increment(value);
      f["range_min"] >> value, scan.range_min(value);
      f["range_max"] >> value, scan.range_max(value);
      std::vector<float> ranges;
      f["ranges"] >> ranges;
      scan.ranges(ranges);
      in.scan = scan;
    }
    if (const auto f = fs["cloud"]; !f.empty()) {
      macsim::client::Cloud cloud;
      cv::Mat points;
      f["stamp"] >> cloud.stamp;
      f["points"] >> points;
      if (!points.empty() && (points.cols != 3 || points.type() != CV_32F))
        throw std::runtime_error(file + ": the cloud is not N x 3 floats");
      for (int i = 0; i < points.rows; ++i)
        cloud.points.push_back(
            {points.at<float>(i, 0), points.at<float>(i, 1), points.at<float>(i, 2)});
      in.cloud = cloud;
    }
  } catch (const cv::Exception& e) {
    throw std::runtime_error(file + ": damaged: " + e.msg);
  }
  return in;
}

std::map<std::string, double> named_features(const Percept& percept, Affordance affordance) {
  const auto values = features(percept, affordance);
  const auto& names = feature_names(affordance);
  std::map<std::string, double> out;
  for (std::size_t i = 0; i < names.size(); ++i) out[names[i]] = values[i];
  return out;
}

const std::vector<std::string>* feature_group(const std::string& name) {
  static const std::map<std::string, std::vector<std::string>> groups = [] {
    std::map<std::string, std::vector<std::string>> g;
    g["camera"] = {"r",        "g",         "b",    "hue",          "area_px",
                   "width_px", "height_px", "fill", "stereo_range", "width_m"};
    g["sweep"] = {"laser_range", "laser_height", "laser_depth", "laser_slope"};
    g["top"] = {"top_length", "top_flatness", "top_curvature", "carried_height"};
    g["cloud"] = grid_names();
    g["shape"] = {"free_width",       "corridor_height",     "corridor_nearest",
                  "shape_height",     "shape_width",         "shape_depth",
                  "shape_recess_max", "shape_recess_median", "shape_top_depth"};
    return g;
  }();
  const auto found = groups.find(name);
  return found == groups.end() ? nullptr : &found->second;
}

const std::vector<std::string>& feature_names(Affordance affordance) {
  auto join = [](std::initializer_list<const char*> names) {
    std::vector<std::string> all;
    for (const char* n : names) {
      const auto& group = *feature_group(n);
      all.insert(all.end(), group.begin(), group.end());
    }
    return all;
  };
  static const std::vector<std::string> base = join({"camera", "sweep"});
  static const std::vector<std::string> stack = join({"camera", "sweep", "top"});
  static const std::vector<std::string> traverse = join({"camera", "sweep", "cloud", "shape"});
  switch (affordance) {
    case Affordance::Stack:
      return stack;
    case Affordance::Traverse:
      return traverse;
    default:
      return base;
  }
}

}  // namespace macsim::affordances
