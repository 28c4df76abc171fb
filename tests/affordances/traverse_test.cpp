// What stands on the floor in a synthetic cloud: its things, a way turned ahead and the trials'
// features of it, the traverse model files taken, and the ways the floor plan finds around what
// blocks and through what is passable.
#include "macsim/affordances/traverse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "learning.h"
#include "macsim/affordances/perception.h"
#include "support/child_process.h"
#include "trial_record.h"

namespace macsim::affordances {
namespace {

namespace af = macsim::affordances;
const double kFloorInBase = -SensorMount{}.base_height;  // base_link z of the floor

/// A post 0.3 m high at (x, y) (base_link), its points every 2 cm up and every 22.5 degrees
/// around, and a square of floor about the robot (points off the grid's cell borders): turned
/// by a quarter, the cloud maps onto itself but for the post.
macsim::client::Cloud post_at(double x, double y) {
  macsim::client::Cloud cloud;
  for (double z = 0.02; z <= 0.3; z += 0.02)
    for (int k = 0; k < 16; ++k)
      cloud.points.push_back({float(x + 0.05 * std::cos(k * M_PI / 8)),
                              float(y + 0.05 * std::sin(k * M_PI / 8)), float(kFloorInBase + z)});
  std::vector<float> along;  // -1.97 ... 1.97, as many each side, none on a cell's border
  for (int i = 0; i < 20; ++i)
    for (double v : {0.1 * i + 0.03, 0.1 * i + 0.07})
      along.insert(along.end(), {float(v), -float(v)});
  for (float a : along)
    for (float b : along) cloud.points.push_back({a, b, float(kFloorInBase)});
  return cloud;
}


/// A post of radius 0.05 m and `height` at (x, y), base_link: points every 2 cm up and every 22.5
/// degrees around.
void add_post(macsim::client::Cloud& cloud, double x, double y, double height) {
  for (double z = 0.02; z <= height; z += 0.02)
    for (int k = 0; k < 16; ++k)
      cloud.points.push_back({float(x + 0.05 * std::cos(k * M_PI / 8)),
                              float(y + 0.05 * std::sin(k * M_PI / 8)), float(kFloorInBase + z)});
}

/// A thing whose cells fill a disc of `radius` about (x, y) (odometry frame).
Thing disc(double x, double y, double radius, bool passable) {
  Thing t;
  for (double dx = -radius; dx <= radius; dx += 0.05)
    for (double dy = -radius; dy <= radius; dy += 0.05)
      if (std::hypot(dx, dy) <= radius) t.cells.push_back({x + dx, y + dy});
  t.centre = {x, y};
  t.judged = true;
  t.passable = passable;
  return t;
}

/// A wall of cells along x at `y`, from x0 to x1.
Thing wall(double y, double x0, double x1) {
  Thing t;
  for (double x = x0; x <= x1; x += 0.05) t.cells.push_back({x, y});
  t.judged = true;
  return t;
}

/// The way's nearest approach to (x, y).
double nearest(const std::vector<Point2>& way, double x, double y) {
  double d = 1e9;
  for (const auto& p : way) d = std::min(d, std::hypot(p[0] - x, p[1] - y));
  return d;
}

TEST(Traverse, ACloudsThingsAreItsReturnsAboveTheFloorGroupedLeavingOutTheRobot) {
  macsim::client::Cloud cloud;
  for (double x = -2; x <= 2; x += 0.1)  // the floor
    for (double y = -2; y <= 2; y += 0.1)
      cloud.points.push_back({float(x), float(y), float(kFloorInBase)});
  add_post(cloud, 1.0, 0.5, 0.3);
  add_post(cloud, 1.0, -0.5, 0.3);
  add_post(cloud, 0.1, 0.0, 0.2);             // on the robot's own body
  macsim::affordances::Pose2 pose{2.0, 1.0, M_PI / 2};  // facing +y in the odometry frame
  const auto things = things_in(cloud, pose);
  ASSERT_EQ(things.size(), 2u);
  for (const auto& t : things) {
    // Base (1, +-0.5) is odometry (2 -+ 0.5, 2).
    EXPECT_NEAR(t.centre[1], 2.0, 0.04);
    EXPECT_NEAR(std::fabs(t.centre[0] - 2.0), 0.5, 0.04);
    EXPECT_NEAR(t.distance, std::hypot(0.95, 0.5), 0.06);
    EXPECT_LT(t.across, 0.3);  // 0.1 m across, over up to 3 cells each way
    EXPECT_EQ(t.points.size(), 14u * 16u) << "all but its lowest ring (2 cm: the floor)";
    EXPECT_FALSE(t.judged);
  }
}

/// A box from (x0, y0) to (x1, y1), `height` high, base_link: its top and sides every 2 cm.
void add_box(macsim::client::Cloud& cloud, double x0, double y0, double x1, double y1,
             double height) {
  for (double x = x0; x <= x1 + 1e-9; x += 0.02)
    for (double y = y0; y <= y1 + 1e-9; y += 0.02)
      cloud.points.push_back({float(x), float(y), float(kFloorInBase + height)});
  for (double z = 0.02; z < height; z += 0.02) {
    for (double x = x0; x <= x1 + 1e-9; x += 0.02) {
      cloud.points.push_back({float(x), float(y0), float(kFloorInBase + z)});
      cloud.points.push_back({float(x), float(y1), float(kFloorInBase + z)});
    }
    for (double y = y0; y <= y1 + 1e-9; y += 0.02) {
      cloud.points.push_back({float(x0), float(y), float(kFloorInBase + z)});
      cloud.points.push_back({float(x1), float(y), float(kFloorInBase + z)});
    }
  }
}

TEST(Traverse, ThingsAreGroupedByHeightAndWhatRisesAboveTheViewIsAWall) {
  macsim::client::Cloud cloud;
  // A joist (4 cm) touching a log-high box (12 cm) ahead, and a wall (0.5 m) to the left with a
  // box (20 cm) touching it.
  add_box(cloud, 1.0, -0.6, 1.05, 0.0, 0.04);
  add_box(cloud, 1.0, 0.02, 1.12, 0.4, 0.12);
  add_box(cloud, -1.0, 1.5, 3.0, 1.6, 0.5);
  add_box(cloud, 2.0, 1.2, 2.25, 1.48, 0.2);
  const auto things = things_in(cloud, macsim::affordances::Pose2{});
  const Thing* joist = nullptr;
  const Thing* log = nullptr;
  const Thing* box = nullptr;
  int walls = 0;
  for (const auto& t : things) {
    if (t.height == Height::Towering) {
      ++walls;
      EXPECT_GT(t.across, 3.0);
      continue;
    }
    if (t.centre[0] < 1.5 && t.centre[1] < -0.1) joist = &t;
    if (t.centre[0] < 1.5 && t.centre[1] > 0.1) log = &t;
    if (t.centre[0] > 1.5) box = &t;
  }
  EXPECT_EQ(walls, 1) << "the wall with the box's side along it, as one";
  ASSERT_TRUE(joist && log) << "the joist apart from what it touches";
  EXPECT_EQ(joist->height, Height::Low);
  EXPECT_NEAR(joist->centre[1], -0.3, 0.06);
  EXPECT_EQ(log->height, Height::High);
  EXPECT_NEAR(log->centre[1], 0.2, 0.06);
  ASSERT_TRUE(box) << "a box touching the wall is a thing of its own, not part of the wall";
  EXPECT_EQ(box->height, Height::High);
  EXPECT_LT(box->across, 0.5);
}

TEST(Traverse, TheWayKeepsClearOfWhatBlocksAndCrossesWhatIsPassable) {
  {
    FloorPlan plan({0, 0}, {4, 0});
    plan.add(disc(2, 0, 0.2, false), 0.3, 0.5);
    const auto way = plan.path();
    ASSERT_FALSE(way.empty());
    EXPECT_EQ(way.front(), (Point2{0, 0}));
    EXPECT_EQ(way.back(), (Point2{4, 0}));
    EXPECT_GE(nearest(way, 2, 0), 0.2 + 0.3 - 0.05) << "its cells, grown by the clearance";
    EXPECT_GT(length(way), 4.05);
  }
  // A corridor 1 m wide closed by a thing across it: crossed when passable, else no way.
  for (bool passable : {true, false}) {
    FloorPlan plan({0, 0}, {4, 0});
    plan.add(wall(0.5, -3, 7), 0.3, 0.5);
    plan.add(wall(-0.5, -3, 7), 0.3, 0.5);
    Thing across;
    for (double y = -0.5; y <= 0.5; y += 0.05) across.cells.push_back({2, y});
    across.judged = true;
    across.passable = passable;
    plan.add(across, 0.3, 0.5);
    const auto way = plan.path();
    if (passable) {
      ASSERT_FALSE(way.empty());
      EXPECT_LT(nearest(way, 2, 0), 0.1);
      EXPECT_LT(length(way), 4.1);
    } else {
      EXPECT_TRUE(way.empty());
    }
  }
}

TEST(Traverse, ItLeavesWhatItStandsAgainstAndNeverEntersABlockedGoal) {
  {
    FloorPlan plan({0, 0}, {3, 0});
    plan.add(disc(0.25, 0, 0.1, false), 0.3, 0.5);  // against its front
    const auto way = plan.path();
    ASSERT_FALSE(way.empty());
    EXPECT_GE(nearest({way.begin() + static_cast<long>(way.size() / 2), way.end()}, 0.25, 0), 0.35);
  }
  {
    FloorPlan plan({0, 0}, {3, 0});
    plan.block({3, 0}, 0.2);
    EXPECT_TRUE(plan.path().empty());
  }
}

TEST(Traverse, ThingsNotYetJudgedAreCrossedOnlyAtAPrice) {
  FloorPlan plan({0, 0}, {4, 0});
  Thing unknown = disc(2, 0, 0.3, false);
  unknown.judged = false;
  plan.add(unknown, 0.3, 0.5);
  const auto way = plan.path();
  ASSERT_FALSE(way.empty());
  EXPECT_GE(nearest(way, 2, 0), 0.3) << "around it, where that is cheap";
}

TEST(Traverse, AWayTurnedAheadSeesWhatStandsAlongIt) {
  // The post about 1 m to the left: the way 90 degrees left has it about 1 m ahead.
  const auto cloud = post_at(-0.07, 0.98);
  const auto left = along(cloud, M_PI / 2);
  EXPECT_DOUBLE_EQ(way_features(cloud).at("corridor_nearest"), 0.0) << "straight ahead is free";
  EXPECT_DOUBLE_EQ(way_features(along(cloud, -M_PI / 2)).at("corridor_nearest"), 0.0)
      << "it is behind";
  // The features of the turned way are a trial's of a cloud taken facing the post.
  const auto facing = post_at(0.98, 0.07);
  const auto a = way_features(left), b = way_features(facing);
  ASSERT_EQ(a.size(), af::feature_names(af::Affordance::Traverse).size());
  EXPECT_NEAR(a.at("corridor_height"), 0.3, 0.02);
  EXPECT_NEAR(a.at("corridor_nearest"), 0.93, 0.005);
  for (const auto& [name, value] : b) EXPECT_NEAR(a.at(name), value, 1e-3) << name;
}

/// A model of the committed rows of `rows` on `features` (empty: all), saved as DIR/traverse.yml.
void save_model(const std::string& rows, const std::vector<std::string>& features,
                const std::string& dir) {
  auto sets = ::affordances::datasets(
      ::affordances::read_csv(macsim::test::source("tests/tools/affordances/" + rows)), features);
  ASSERT_EQ(sets.size(), 1u);
  const auto& data = sets.begin()->second;
  std::filesystem::create_directories(dir);
  ::affordances::fit(data, ::affordances::evaluate(data)).save(dir + "/traverse.yml");
}

TEST(Traverse, OnlyATraverseModelOnTheCloudsFeaturesIsTaken) {
  macsim::test::TempDir dir("navigate_models_");
  save_model("traverse_trials.csv", *af::feature_group("shape"), dir.path() + "/shape");
  const auto model = load_traverse_model(dir.path() + "/shape");
  EXPECT_EQ(model.info().features, *af::feature_group("shape"));
  // The grid's cells are a cloud's too.
  save_model("traverse_trials.csv", *af::feature_group("cloud"), dir.path() + "/cloud");
  EXPECT_EQ(load_traverse_model(dir.path() + "/cloud").info().features,
            *af::feature_group("cloud"));
  // Asked by name, as the navigator asks it (a way's features hold the cameras' too, which it
  // leaves out), it gives the trials their labels.
  auto sets = ::affordances::datasets(
      ::affordances::read_csv(macsim::test::source("tests/tools/affordances/traverse_trials.csv")));
  const auto& rows = sets.at("traverse");
  int agree = 0;
  for (int i = 0; i < rows.features.rows; ++i) {
    std::map<std::string, double> named;
    for (std::size_t k = 0; k < rows.feature_names.size(); ++k)
      named[rows.feature_names[k]] = rows.features.at<float>(i, static_cast<int>(k));
    agree += model.predict(named).label == rows.classes[static_cast<std::size_t>(rows.labels[i])];
  }
  EXPECT_GE(agree, rows.features.rows * 9 / 10) << agree << " of " << rows.features.rows;
  EXPECT_GT(model.info().held_out_accuracy, 0.8);

  save_model("traverse_trials.csv", {}, dir.path() + "/all");
  try {
    load_traverse_model(dir.path() + "/all");
    ADD_FAILURE() << "a model on the cameras' features was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--features shape"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("hue"), std::string::npos) << e.what();
  }
  save_model("lift_trials.csv", {}, dir.path() + "/lift");  // a lift model named traverse.yml
  try {
    load_traverse_model(dir.path() + "/lift");
    ADD_FAILURE() << "a lift model was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not traverse"), std::string::npos) << e.what();
  }
  try {
    load_traverse_model(dir.path() + "/none");
    ADD_FAILURE() << "a missing model was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir.path() + "/none/traverse.yml"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace macsim::affordances
