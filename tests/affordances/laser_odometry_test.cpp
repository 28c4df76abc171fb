// Laser odometry on synthetic clouds: what stands still is what rises above what the robot pushes,
// and a look is laid onto the map even when the wheels slipped far.
#include "macsim/affordances/laser_odometry.h"

#include <gtest/gtest.h>

#include <cmath>

#include "macsim/affordances/perception.h"

namespace macsim::affordances {
namespace {

const double kFloorZ = -SensorMount{}.base_height;  // the floor's z in base_link

TEST(LaserOdometry, WhatStandsStillIsWhatRisesAboveWhatTheRobotPushes) {
  macsim::client::Cloud cloud;
  // Returns straight ahead at 2 m: 10 cm high (a log: left out), 30 cm (kept), 70 cm (above the
  // walls: left out); at 30 cm high: 0.4 m away (its own crane: out), 9 m (kept), 10 m (out).
  for (double h : {0.1, 0.3, 0.7}) cloud.points.push_back({2.0f, 0.0f, float(kFloorZ + h)});
  for (double r : {0.4, 9.0, 10.0}) cloud.points.push_back({0.0f, float(r), float(kFloorZ + 0.3)});
  const auto still = static_structure(cloud, macsim::affordances::Pose2{1.0, 2.0, M_PI / 2});
  ASSERT_EQ(still.size(), 2u);
  std::vector<Point2> expected{{1.0, 4.0},
                               {-8.0, 2.0}};  // base (2, 0) and (0, 9), turned a quarter
  for (const auto& e : expected) {
    bool found = false;
    for (const auto& p : still) found |= std::hypot(p[0] - e[0], p[1] - e[1]) < 1e-5;
    EXPECT_TRUE(found) << e[0] << "," << e[1];
  }
}

TEST(LaserOdometry, LaserOdometryLaysALookOntoTheMapEvenWhenTheWheelsSlippedFar) {
  // A map of walls along x (y = +-1.5) and across (x = 5).
  std::vector<Point2> map;
  for (double x = -1; x <= 5; x += 0.05) map.push_back({x, 1.5}), map.push_back({x, -1.5});
  for (double y = -1.5; y <= 1.5; y += 0.05) map.push_back({5, y});
  StaticMap kept;
  kept.add(map);
  const auto once = kept.points().size();
  EXPECT_GE(once, map.size() - 2) << "a point per 5 cm cell (the corners are two)";
  kept.add(map);
  EXPECT_EQ(kept.points().size(), once) << "seen again: nothing new";
  // The part of it a look sees, from a robot whose wheels are off by (dx, dy): within the reach
  // of one fit, and beyond it (a track slipping 0.9 m against something).
  for (const auto& [dx, dy] : {std::pair{0.1, -0.05}, std::pair{0.6, 0.2}, std::pair{-0.9, 0.0}}) {
    std::vector<Point2> now;
    for (const auto& p : map)
      if (p[0] > 1) now.push_back({p[0] - dx, p[1] - dy});
    const auto shift = align(map, now);
    ASSERT_TRUE(shift) << dx << "," << dy;
    EXPECT_NEAR((*shift)[0], dx, 0.02);
    EXPECT_NEAR((*shift)[1], dy, 0.02);
  }
  // Walls along x alone leave the shift along them open: no fit, the wheels' word stands.
  std::vector<Point2> corridor, seen;
  for (double x = -1; x <= 5; x += 0.05)
    corridor.push_back({x, 1.5}), corridor.push_back({x, -1.5});
  for (const auto& p : corridor) seen.push_back({p[0] - 0.3, p[1]});
  EXPECT_FALSE(align(corridor, seen));
  // A guess ("it did not move") is taken when it lays the look clearly better than the wheels.
  std::vector<Point2> stuck;
  for (const auto& p : map)
    if (p[0] > 1) stuck.push_back({p[0] - 0.5, p[1]});
  const auto from_guess = align(map, stuck, {{0.5, 0.0}});
  ASSERT_TRUE(from_guess);
  EXPECT_NEAR((*from_guess)[0], 0.5, 0.02);
}

}  // namespace
}  // namespace macsim::affordances
