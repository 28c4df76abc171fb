// kurt_demo's laser map on synthetic clouds: the wall's line and the opening in it (or none
// while the leaf closes it), corridors, the obstacle grid.
#include "macsim/affordances/laser_map.h"

#include <gtest/gtest.h>

#include <cmath>

namespace macsim::affordances {
namespace {

/// A wall across x = `distance` from y0 to y1 (points every 2 cm), at the height the slice keeps.
void wall(macsim::client::Cloud& cloud, double distance, double y0, double y1, double z = 0.39) {
  for (double y = y0; y <= y1; y += 0.02) {
    cloud.points.push_back({float(distance), float(y), float(z)});
  }
}

const KurtGeometry kGeometry;

TEST(KurtDemoLaserMap, SliceKeepsTheHeightBandAndTheRange) {
  macsim::client::Cloud cloud;
  cloud.points = {{2, 0, 0.39f}, {2, 0, 0.0f}, {0.3f, 0, 0.39f}, {9, 0, 0.39f}};
  const auto points = slice(cloud, kGeometry, 0.505, 0.615, 0.6, 6.0);
  ASSERT_EQ(points.size(), 1u);  // 0.39 + 0.167 above the floor, 2 m away
  EXPECT_DOUBLE_EQ(points[0].x, 2.0);
}

TEST(KurtDemoLaserMap, FindsTheOpeningInAWallAndNoneWhenItIsClosed) {
  macsim::client::Cloud open;
  wall(open, 2.0, -2.0, -0.42);
  wall(open, 2.0, 0.42, 2.0);
  const auto passage = find_passage(slice(open, kGeometry, 0.505, 0.615, 0.6, 6.0), 0.6);
  ASSERT_TRUE(passage.has_value());
  EXPECT_NEAR(passage->centre.x, 2.0, 0.01);
  EXPECT_NEAR(passage->centre.y, 0.0, 0.02);
  EXPECT_NEAR(passage->width, 0.84, 0.03);
  EXPECT_NEAR(passage->normal.x, 1.0, 1e-6);  // across the wall, away from the robot

  // The leaf closes it 0.1 m in front of the wall: still the wall's, no opening.
  macsim::client::Cloud closed = open;
  wall(closed, 1.9, -0.42, 0.42);
  EXPECT_FALSE(find_passage(slice(closed, kGeometry, 0.505, 0.615, 0.6, 6.0), 0.6).has_value());
  // Too few points for a wall.
  EXPECT_FALSE(find_passage({{1, 0}, {1, 1}}, 0.6).has_value());
}

TEST(KurtDemoLaserMap, ObstacleMapTellsFreeWaysFromBlockedOnes) {
  macsim::client::Cloud cloud;
  cloud.points = {{1.0f, 0.0f, 0.0f}};  // a can's worth, 0.17 m above the floor, 1 m ahead
  ObstacleMap map;
  // The robot stood at (1, 1) facing +y: the point lands at (1, 2) in the map's frame.
  map.add(cloud, kGeometry, 1.0, 1.0, M_PI / 2);
  EXPECT_EQ(map.cells(), 1u);
  EXPECT_NEAR(map.clearance({1.0, 2.0}, 1.0), 0.035, 0.04);
  EXPECT_FALSE(map.free({1.0, 1.0}, {1.0, 3.0}, 0.25));
  EXPECT_TRUE(map.free({0.0, 1.0}, {0.0, 3.0}, 0.25));
  // The way to the object itself is free when the object is the goal.
  EXPECT_TRUE(map.free({1.0, 1.0}, {1.0, 1.9}, 0.25, {1.0, 2.0}, 0.15));
  map.clear({1.0, 2.0}, 0.1);
  EXPECT_EQ(map.cells(), 0u);
  EXPECT_TRUE(map.free({1.0, 1.0}, {1.0, 3.0}, 0.25));
}

TEST(KurtDemoLaserMap, TheFirstBlockedCellIsTheNearestOnTheWayAndWhatIsLetPassStaysFree) {
  macsim::client::Cloud cloud;
  cloud.points = {{1.0f, 0.0f, 0.0f}, {2.0f, 0.1f, 0.0f}};  // two things ahead, at 1 and 2 m
  ObstacleMap map;
  map.add(cloud, kGeometry, 0.0, 0.0, 0.0);
  const auto first = map.first_blocked({0.0, 0.0}, {3.0, 0.0}, 0.25);
  ASSERT_TRUE(first.has_value());
  EXPECT_NEAR(first->x, 1.025, 1e-9);  // the middle of the 5 cm cell holding (1, 0)
  EXPECT_NEAR(first->y, 0.025, 1e-9);
  EXPECT_FALSE(map.first_blocked({0.0, 1.0}, {3.0, 1.0}, 0.25).has_value());  // beside both
  // The first judged traversable: the next is the second, and a later cloud does not bring the
  // first back.
  map.let_pass(*first);
  map.add(cloud, kGeometry, 0.0, 0.0, 0.0);
  const auto next = map.first_blocked({0.0, 0.0}, {3.0, 0.0}, 0.25);
  ASSERT_TRUE(next.has_value());
  EXPECT_NEAR(next->x, 2.025, 1e-9);
  map.let_pass(*next);
  EXPECT_TRUE(map.free({0.0, 0.0}, {3.0, 0.0}, 0.25));
  EXPECT_EQ(map.cells(), 0u);
  // Stalled against the first after all: it blocks again, and a later cloud keeps it.
  map.block(*first, 0.05);
  map.add(cloud, kGeometry, 0.0, 0.0, 0.0);
  const auto again = map.first_blocked({0.0, 0.0}, {3.0, 0.0}, 0.25);
  ASSERT_TRUE(again.has_value());
  EXPECT_NEAR(again->x, 1.025, 0.05);
}

TEST(KurtDemoLaserMap, CorridorIgnoresTheGoalButNotWhatIsInFrontOfIt) {
  const std::vector<Point> points{{1.0, 0.05}, {2.0, 0.0}};
  EXPECT_FALSE(corridor_free(points, {2.0, 0.0}, 0.2, 0.15));
  EXPECT_TRUE(corridor_free({{2.0, 0.0}}, {2.0, 0.0}, 0.2, 0.15));
  EXPECT_TRUE(corridor_free(points, {0.0, 2.0}, 0.2, 0.15));
}

}  // namespace
}  // namespace macsim::affordances
