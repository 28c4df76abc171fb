#include "macsim/affordances/perception.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace macsim::affordances {
namespace {

/// A sweep of the scanner standing still (plane x-z), cast against the floor and a profile of
/// segments given in base_link (x, z): what the simulator's ray caster would return, noise-free.
macsim::client::Laser::Scan sweep(const std::vector<std::array<double, 4>>& segments) {
  const SensorMount m;
  macsim::client::Laser::Scan scan;
  scan.angle_min(-M_PI / 2);
  scan.angle_increment(M_PI / 180);
  scan.range_min(0.08);
  scan.range_max(10);
  for (int i = 0; i < 181; ++i) {
    const double a = -M_PI / 2 + i * M_PI / 180, dx = std::cos(a), dz = std::sin(a);
    double best = std::numeric_limits<double>::infinity();
    if (dz < 0) best = (m.laser_z + m.base_height) / -dz;  // the floor
    for (const auto& s : segments) {                       // x0, z0, x1, z1
      const double ex = s[2] - s[0], ez = s[3] - s[1];
      const double den = dx * ez - dz * ex;
      if (std::fabs(den) < 1e-12) continue;
      const double t = ((s[0] - m.laser_x) * ez - (s[1] - m.laser_z) * ex) / den;
      const double u = ((s[0] - m.laser_x) * dz - (s[1] - m.laser_z) * dx) / den;
      if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
    }
    scan.ranges().push_back(std::isfinite(best) && best < 10
                                ? static_cast<float>(best)
                                : std::numeric_limits<float>::infinity());
  }
  return scan;
}

const double kFloor = -SensorMount{}.base_height;

TEST(Perception, TheLaserFindsABoxItsRangeHeightAndSteepFace) {
  // A box 8 cm high from x = 1.0 to 1.1.
  Percept p;
  perceive_scan(
      sweep({{1.0, kFloor, 1.0, kFloor + 0.08}, {1.0, kFloor + 0.08, 1.1, kFloor + 0.08}}),
      SensorMount{}, p);
  ASSERT_TRUE(p.laser_hit);
  EXPECT_NEAR(p.laser_range, 1.0, 0.01);
  EXPECT_NEAR(p.laser_height, 0.08, 0.025);  // beams are a degree apart
  EXPECT_GT(p.laser_slope, 60 * M_PI / 180);
}

TEST(Perception, TheLaserMeasuresARampsSlope) {
  // A 20 degree ramp from its foot at x = 0.8 up to 0.15 m.
  const double angle = 20 * M_PI / 180, depth = 0.15 / std::tan(angle);
  Percept p;
  perceive_scan(sweep({{0.8, kFloor, 0.8 + depth, kFloor + 0.15}}), SensorMount{}, p);
  ASSERT_TRUE(p.laser_hit);
  EXPECT_NEAR(p.laser_slope, angle, 4 * M_PI / 180);
  EXPECT_NEAR(p.laser_height, 0.15, 0.03);
  EXPECT_NEAR(p.laser_range, 0.8, 0.05);
}

TEST(Perception, TheTopOfABoxIsFlatTheTopOfASphereCurved) {
  // A box 12 cm high from x = 0.9 to 1.1: a flat top about 20 cm long.
  Percept box;
  perceive_scan(
      sweep({{0.9, kFloor, 0.9, kFloor + 0.12}, {0.9, kFloor + 0.12, 1.1, kFloor + 0.12}}),
      SensorMount{}, box);
  // Beams a degree apart graze the top 4-7 cm apart: less than its length.
  EXPECT_GT(box.top_length, 0.1);
  EXPECT_LE(box.top_length, 0.2 + 1e-9);
  EXPECT_LT(box.top_flatness, 0.003);
  EXPECT_NEAR(box.top_curvature, 0.0, 1.0);
  // A sphere of 10 cm radius resting at x = 1.0, as 40 short chords.
  std::vector<std::array<double, 4>> circle;
  for (int i = 0; i < 40; ++i) {
    const double a0 = M_PI * i / 40, a1 = M_PI * (i + 1) / 40;
    circle.push_back({1.0 - 0.1 * std::cos(a0), kFloor + 0.1 + 0.1 * std::sin(a0),
                      1.0 - 0.1 * std::cos(a1), kFloor + 0.1 + 0.1 * std::sin(a1)});
  }
  Percept sphere;
  perceive_scan(sweep(circle), SensorMount{}, sphere);
  EXPECT_NEAR(sphere.laser_height, 0.2, 0.02);
  EXPECT_LT(sphere.top_curvature, -3.0);  // a circle of radius R: -1/R = -10 per metre
  EXPECT_LT(sphere.top_length, box.top_length);
}

/// A cloud in base_link: the floor ahead on a 1 cm grid and boxes (x0, x1, y0, y1, height)
/// as points on their faces and top, as one turn of the scanner would see them (noise-free).
macsim::client::Cloud cloud(const std::vector<std::array<double, 5>>& boxes) {
  macsim::client::Cloud c;
  auto inside = [&](double x, double y) {
    for (const auto& b : boxes)
      if (x >= b[0] && x <= b[1] && y >= b[2] && y <= b[3]) return true;
    return false;
  };
  for (double x = 0.2; x < 2.0; x += 0.01)
    for (double y = -0.5; y < 0.5; y += 0.01)
      if (!inside(x, y)) c.points.push_back({float(x), float(y), float(kFloor)});
  for (const auto& b : boxes) {
    for (double z = 0; z <= b[4]; z += 0.01)
      for (double y = b[2]; y <= b[3]; y += 0.01)
        c.points.push_back({float(b[0]), float(y), float(kFloor + z)});
    for (double x = b[0]; x <= b[1]; x += 0.01)
      for (double y = b[2]; y <= b[3]; y += 0.01)
        c.points.push_back({float(x), float(y), float(kFloor + b[4])});
    for (double z = 0; z <= b[4]; z += 0.01)
      for (double x = b[0]; x <= b[1]; x += 0.01) {
        c.points.push_back({float(x), float(b[2]), float(kFloor + z)});
        c.points.push_back({float(x), float(b[3]), float(kFloor + z)});
      }
  }
  return c;
}

TEST(Perception, TheCloudShowsWhatBlocksTheCorridorAndHowWideAPassageIs) {
  Percept floor;
  perceive_cloud(cloud({}), SensorMount{}, floor);
  EXPECT_NEAR(floor.free_width, GroundGrid::kWidth, 1e-9);
  EXPECT_NEAR(floor.corridor_height, 0.0, 1e-6);
  EXPECT_EQ(floor.corridor_nearest, 0.0);
  ASSERT_EQ(floor.grid.size(), static_cast<std::size_t>(GroundGrid::kRows * GroundGrid::kColumns *
                                                        GroundGrid::kValues));
  EXPECT_NEAR(floor.grid[4], 0.0, 1e-3);  // the floor is level

  // A box 20 cm high across the middle, from x = 0.8: the corridor is blocked there.
  Percept box;
  perceive_cloud(cloud({{0.8, 1.0, -0.1, 0.1, 0.2}}), SensorMount{}, box);
  EXPECT_NEAR(box.corridor_height, 0.2, 0.011);
  EXPECT_NEAR(box.corridor_nearest, 0.8, 0.011);
  EXPECT_LT(box.free_width, 0.05);
  // Its cell (row 2 and 3: x 0.65-1.05; columns 2 and 3: y -0.15-0.15) is high, with a slope.
  const std::size_t cell = (2 * GroundGrid::kColumns + 2) * GroundGrid::kValues;
  EXPECT_NEAR(box.grid[cell + 3], 0.2, 0.011);
  EXPECT_GT(box.grid[cell + 4], 0.3);
  EXPECT_LT(box.grid[cell + 0], box.grid[cell + 1]);  // nearest before farthest

  // Two walls 40 cm high with 36 cm between them.
  Percept passage;
  perceive_cloud(cloud({{0.8, 1.2, -0.48, -0.18, 0.39}, {0.8, 1.2, 0.18, 0.48, 0.39}}),
                 SensorMount{}, passage);
  EXPECT_NEAR(passage.free_width, 0.36, 0.011);
  EXPECT_NEAR(passage.corridor_height, 0.39, 0.011);  // a wall within 0.2 m of the axis
}

/// The near half of a ball of `radius` on the floor centred `x` ahead: what a scanner above and
/// behind it sees.
macsim::client::Cloud ball(double x, double radius) {
  auto c = cloud({});
  for (double a = -M_PI / 2; a <= M_PI / 2; a += 0.02)    // across
    for (double e = -M_PI / 4; e <= M_PI / 2; e += 0.02)  // up from its middle
      c.points.push_back({float(x - radius * std::cos(e) * std::cos(a)),
                          float(radius * std::cos(e) * std::sin(a)),
                          float(kFloor + radius + radius * std::sin(e))});
  return c;
}

TEST(Perception, TheShapeTellsARoundTopFromAFaceWhereverItStands) {
  // A box 20 cm high, 30 cm deep: its top begins at its front.
  Percept box;
  perceive_cloud(cloud({{0.8, 1.1, -0.15, 0.15, 0.2}}), SensorMount{}, box);
  EXPECT_NEAR(box.shape_height, 0.2, 0.011);
  EXPECT_NEAR(box.shape_width, 0.3, 0.011);
  EXPECT_NEAR(box.shape_depth, 0.3, 0.011);
  EXPECT_NEAR(box.shape_top_depth, 0.3, 0.011);
  EXPECT_LT(box.shape_recess_max, 0.011);
  // A ball of 10 cm radius: its top lies behind its front (a radius, less the 4.4 cm the band
  // 1 cm below its top reaches forward), and little of it is top.
  for (double x : {0.8, 1.1}) {
    Percept b;
    perceive_cloud(ball(x, 0.1), SensorMount{}, b);
    EXPECT_NEAR(b.shape_height, 0.2, 0.005) << x;
    EXPECT_NEAR(b.shape_width, 0.2, 0.005) << x;
    EXPECT_NEAR(b.shape_recess_max, 0.1 - std::sqrt(2 * 0.1 * 0.01), 0.01) << x;
    EXPECT_GT(b.shape_recess_median, 0.03) << x;
    EXPECT_LT(b.shape_top_depth, 0.05) << x;
  }
  // The same thing further ahead reads the same, where the grid's cells change.
  Percept far_box;
  perceive_cloud(cloud({{1.1, 1.4, -0.15, 0.15, 0.2}}), SensorMount{}, far_box);
  EXPECT_NEAR(far_box.shape_depth, box.shape_depth, 1e-6);
  EXPECT_NEAR(far_box.shape_recess_max, box.shape_recess_max, 1e-6);
  // The floor alone has no shape.
  Percept floor;
  perceive_cloud(cloud({}), SensorMount{}, floor);
  EXPECT_EQ(floor.shape_height, 0.0);
  EXPECT_EQ(floor.shape_recess_max, 0.0);
}

TEST(Perception, TheFloorAloneIsNoHit) {
  Percept p;
  perceive_scan(sweep({}), SensorMount{}, p);
  EXPECT_FALSE(p.laser_hit);
}

TEST(Perception, TheCamerasFindTheObjectNotTheCraneAtTheEdgeAndRangeItByStereo) {
  macsim::client::StereoFrame f;
  f.focal = 300;
  f.cx = 160;
  f.cy = 120;
  f.baseline = 0.1;
  f.left = cv::Mat(240, 320, CV_8UC3, cv::Scalar(150, 150, 150));
  f.right = f.left.clone();
  // The crane's yellow boom cut by the bottom right corner, larger than the object.
  for (cv::Mat* image : {&f.left, &f.right})
    cv::rectangle(*image, {280, 180}, {320, 240}, cv::Scalar(20, 200, 230), cv::FILLED);
  // A red ball, 10 px further left in the right image: 300 * 0.1 / 10 = 3 m.
  cv::circle(f.left, {170, 150}, 15, cv::Scalar(20, 20, 220), cv::FILLED);
  cv::circle(f.right, {160, 150}, 15, cv::Scalar(20, 20, 220), cv::FILLED);
  Percept p;
  perceive_image(f, p);
  ASSERT_TRUE(p.seen);
  EXPECT_GT(p.r, 0.8);
  EXPECT_LT(p.g, 0.15);
  EXPECT_TRUE(p.hue < 10 || p.hue > 350) << p.hue;
  EXPECT_NEAR(p.width_px, 31, 1);
  EXPECT_NEAR(p.fill, M_PI / 4, 0.05);
  EXPECT_NEAR(p.stereo_range, 3.0, 0.05);
  EXPECT_NEAR(p.width_m, 31 * 3.0 / 300, 0.01);
  EXPECT_NEAR(p.bearing, std::atan2(160 - 170, 300), 0.01);
  EXPECT_EQ(features(p).size(), feature_names().size());
}

TEST(Perception, NothingColouredIsNothingSeen) {
  macsim::client::StereoFrame f;
  f.focal = 300;
  f.baseline = 0.1;
  f.left = cv::Mat(240, 320, CV_8UC3, cv::Scalar(150, 150, 150));
  f.right = f.left.clone();
  Percept p;
  perceive_image(f, p);
  EXPECT_FALSE(p.seen);
}

}  // namespace
}  // namespace macsim::affordances
