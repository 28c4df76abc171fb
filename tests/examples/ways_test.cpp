// kurt_navigate's parts on synthetic clouds: a cloud turned so that a way runs ahead and the
// trials' features of it, the things of a cloud, the floor plan's ways around and through them,
// the model files it takes, and what it counts as driven through and around.
#include "ways.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "learning.h"
#include "macsim/affordances/perception.h"
#include "support/child_process.h"
#include "trial_record.h"

namespace kurt_navigate {
namespace {

namespace af = macsim::affordances;
const double kFloor = -af::SensorMount{}.base_height;  // the floor's z in base_link

/// A post 0.3 m high at (x, y) (base_link), its points every 2 cm up and every 22.5 degrees
/// around, and a square of floor about the robot (points off the grid's cell borders): turned
/// by a quarter, the cloud maps onto itself but for the post.
macsim::client::Cloud post_at(double x, double y) {
  macsim::client::Cloud cloud;
  for (double z = 0.02; z <= 0.3; z += 0.02)
    for (int k = 0; k < 16; ++k)
      cloud.points.push_back({float(x + 0.05 * std::cos(k * M_PI / 8)),
                              float(y + 0.05 * std::sin(k * M_PI / 8)), float(kFloor + z)});
  std::vector<float> along;  // -1.97 ... 1.97, as many each side, none on a cell's border
  for (int i = 0; i < 20; ++i)
    for (double v : {0.1 * i + 0.03, 0.1 * i + 0.07})
      along.insert(along.end(), {float(v), -float(v)});
  for (float a : along)
    for (float b : along) cloud.points.push_back({a, b, float(kFloor)});
  return cloud;
}

TEST(NavigateWays, AWayTurnedAheadSeesWhatStandsAlongIt) {
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

TEST(NavigateWays, OnlyATraverseModelOnTheCloudsFeaturesIsTaken) {
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

TEST(NavigateWays, WhatStandsStillIsWhatRisesAboveWhatTheRobotPushes) {
  macsim::client::Cloud cloud;
  // Returns straight ahead at 2 m: 10 cm high (a log: left out), 30 cm (kept), 70 cm (above the
  // walls: left out); at 30 cm high: 0.4 m away (its own crane: out), 9 m (kept), 10 m (out).
  for (double h : {0.1, 0.3, 0.7}) cloud.points.push_back({2.0f, 0.0f, float(kFloor + h)});
  for (double r : {0.4, 9.0, 10.0}) cloud.points.push_back({0.0f, float(r), float(kFloor + 0.3)});
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

TEST(NavigateWays, LaserOdometryLaysALookOntoTheMapEvenWhenTheWheelsSlippedFar) {
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

TEST(NavigateWays, ThingsOnThePathAreDrivenThroughAndThoseBesideItAround) {
  Sightings s;
  macsim::client::Cloud cloud;
  auto thing = [&](double x, double y) {
    for (double dx = -0.05; dx <= 0.05; dx += 0.02)
      for (double dy = -0.05; dy <= 0.05; dy += 0.02)
        cloud.points.push_back({float(x + dx), float(y + dy), float(kFloor + 0.1)});
  };
  thing(1.0, 0.0);  // on the way
  thing(1.5, 0.6);  // beside it
  thing(2.0, 1.8);  // far off
  for (double y = -2.0; y <= 2.0; y += 0.05)
    cloud.points.push_back({2.9f, float(y), float(kFloor + 0.2)});  // a wall: not a thing
  // Taken facing +y from (1.5, -0.5): the point (x, y) is at (y + 0.5, 1.5 - x) in base_link.
  const macsim::affordances::Pose2 at{1.5, -0.5, M_PI / 2};
  macsim::client::Cloud turned;
  for (const auto& q : cloud.points) turned.points.push_back({q[1] + 0.5f, 1.5f - q[0], q[2]});
  s.add(turned, at);
  for (double x = 0; x <= 3.0; x += 0.05) s.pass({x, 0, 0});
  const auto counts = s.count(0.22);
  EXPECT_EQ(counts.seen, 3);
  EXPECT_EQ(counts.through, 1);
  EXPECT_EQ(counts.around, 1);
}

}  // namespace
}  // namespace kurt_navigate

