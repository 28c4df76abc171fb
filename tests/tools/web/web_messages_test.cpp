// macsim_web's messages from wire types: what the page is sent, parsed back as JSON.
#include "macsim/images/image_files.h"
#include "web_messages.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "macsim/dds/convert.h"

namespace macsim::web {
namespace {

using nlohmann::json;
namespace mm = macsim_msgs::msg::dds_;

Objects two_objects() {
  Objects objects;
  for (uint32_t id : {3u, 7u}) {
    mm::ObjectState_ state;
    state.id(id);
    auto& o = state.object();
    o.id(id);
    o.name(id == 3 ? "red_box" : "blue_can");
    mm::Component_ c;
    c.shape(id == 3 ? mm::SHAPE_BOX : mm::SHAPE_CYLINDER);
    c.size({0.1, 0.2, 0.3});
    c.color({0.9f, 0.1f, 0.1f, 1.0f});
    c.pose().orientation().w(1);
    o.components().push_back(c);
    o.pose().position().x(1.23456);
    o.pose().orientation().w(1);
    objects[id] = state;
  }
  return objects;
}

TEST(WebMessages, TheSceneHoldsEveryObjectWithItsShapes) {
  const json scene = json::parse(scene_message(two_objects(), 42, "kurt"));
  EXPECT_EQ(scene["type"], "scene");
  EXPECT_EQ(scene["domain"], 42);
  ASSERT_EQ(scene["objects"].size(), 2u);
  EXPECT_EQ(scene["objects"][0]["id"], 3);
  EXPECT_EQ(scene["objects"][0]["name"], "red_box");
  EXPECT_EQ(scene["objects"][1]["components"][0]["shape"], mm::SHAPE_CYLINDER);
  EXPECT_DOUBLE_EQ(scene["objects"][1]["components"][0]["size"][2], 0.3);
  EXPECT_DOUBLE_EQ(scene["objects"][0]["pose"][0], 1.235);  // to the millimetre
}

TEST(WebMessages, AnUpdateCarriesPosesAndTheRobotOnlyOnceKnown) {
  RobotView robot;
  json update = json::parse(update_message(two_objects(), 12.5, 0.987, robot));
  EXPECT_EQ(update["type"], "update");
  EXPECT_DOUBLE_EQ(update["time"], 12.5);
  EXPECT_DOUBLE_EQ(update["rtf"], 0.99);
  EXPECT_EQ(update["objects"]["7"].size(), 7u);
  EXPECT_FALSE(update.contains("robot"));
  robot.known = true;
  robot.pose = {1, 2, 0.167, 0, 0, 0.7071, 0.7071};
  robot.slew = 0.3;
  robot.magnet = true;
  robot.held = "can";
  update = json::parse(update_message(two_objects(), 12.5, 1.0, robot));
  EXPECT_DOUBLE_EQ(update["robot"]["pose"][1], 2);
  EXPECT_DOUBLE_EQ(update["robot"]["crane"][0], 0.3);
  EXPECT_EQ(update["robot"]["held"], "can");
}

TEST(WebMessages, AScanSaysNullWhereNothingEchoed) {
  sensor_msgs::msg::dds_::LaserScan_ scan;
  scan.range_min(0.02f);
  scan.range_max(30.0f);
  scan.angle_min(-1.0f);
  scan.angle_increment(0.5f);
  scan.ranges({1.23456f, std::numeric_limits<float>::infinity(), 0.0f, std::nanf(""), 40.0f});
  const json message = json::parse(scan_message(scan));
  ASSERT_EQ(message["ranges"].size(), 5u);
  EXPECT_NEAR(message["ranges"][0].get<double>(), 1.235, 1e-9);
  for (int i : {1, 2, 3, 4}) EXPECT_TRUE(message["ranges"][i].is_null()) << i;
}

TEST(WebMessages, ACloudIsThinnedToItsCapAndKeepsOnlyFinitePoints) {
  client::Cloud cloud;
  cloud.stamp = 3.0;
  for (int i = 0; i < 10000; ++i) cloud.points.push_back({i * 0.001f, 1.0f, 0.5f});
  cloud.points[0][1] = std::nanf("");
  const json message = json::parse(cloud_message(cloud, 1000));
  const auto count = message["points"].size() / 3;
  EXPECT_LE(count, 1000u);
  EXPECT_GE(count, 990u);
  EXPECT_EQ(message["points"].size() % 3, 0u);
  EXPECT_DOUBLE_EQ(message["points"][1], 1.0);
}

TEST(WebMessages, AnImageIsItsEyeThenAJpegOfTheSameSize) {
  cv::Mat bgr(48, 64, CV_8UC3, cv::Scalar(10, 200, 30));
  const std::string frame = image_frame('R', bgr, 80);
  ASSERT_GT(frame.size(), 3u);
  EXPECT_EQ(frame[0], 'R');
  const std::vector<uchar> jpeg(frame.begin() + 1, frame.end());
  const cv::Mat back = macsim::images::decode_image(jpeg.data(), jpeg.size());
  EXPECT_EQ(back.size(), bgr.size());
  EXPECT_NEAR(back.at<cv::Vec3b>(20, 20)[1], 200, 4);
  EXPECT_TRUE(image_frame('L', cv::Mat(), 80).empty());
}

TEST(WebMessages, APlanCarriesItsStepsAndItsThingsInTheWorld) {
  // The odometry frame: the robot started at (1, 2) facing +y; it stands 0.5 m ahead of it now.
  geometry_msgs::msg::dds_::Pose_ truth, odom;
  truth.position().x(1.0);
  truth.position().y(2.5);
  truth.orientation(dds::yaw_quaternion(M_PI / 2));
  odom.position().x(0.5);
  odom.orientation(dds::yaw_quaternion(0));
  const auto frame = odom_in_world(truth, odom);
  EXPECT_NEAR(frame[0], 1.0, 1e-9);
  EXPECT_NEAR(frame[1], 2.0, 1e-9);
  EXPECT_NEAR(frame[2], M_PI / 2, 1e-9);

  plan_msgs::msg::dds_::Plan_ plan;
  plan.goal("through-door");
  plan.round(2);
  plan.current(1);
  plan_msgs::msg::dds_::PlanStep_ step;
  step.action("(go start red_1)");
  step.predicted("(robot-at red_1), not (robot-at start)");
  step.probability(1.0);
  step.perceived("as predicted");
  step.status(plan_msgs::msg::dds_::STEP_AS_PREDICTED);
  plan.steps().push_back(step);
  step.action("(lift red_1)");
  step.probability(0.4567);
  step.perceived("");
  step.status(plan_msgs::msg::dds_::STEP_UNDER_WAY);
  plan.steps().push_back(step);
  plan_msgs::msg::dds_::JudgedThing_ thing;
  thing.name("red_1");
  thing.x(1.0);  // 1 m ahead of where the robot started: 1 m along +y in the world
  thing.y(0.0);
  thing.label("liftable");
  thing.confidence(0.456);
  plan.things().push_back(thing);

  const json m = json::parse(plan_message(plan, frame));
  EXPECT_EQ(m["type"], "plan");
  EXPECT_EQ(m["goal"], "through-door");
  EXPECT_EQ(m["round"], 2);
  EXPECT_EQ(m["current"], 1);
  EXPECT_EQ(m["outcome"], "");
  ASSERT_EQ(m["steps"].size(), 2u);
  EXPECT_EQ(m["steps"][0]["status"], "as predicted");
  EXPECT_EQ(m["steps"][1]["status"], "under way");
  EXPECT_DOUBLE_EQ(m["steps"][1]["probability"].get<double>(), 0.457);
  EXPECT_EQ(m["steps"][1]["action"], "(lift red_1)");
  ASSERT_EQ(m["things"].size(), 1u);
  EXPECT_EQ(m["things"][0]["label"], "liftable");
  EXPECT_DOUBLE_EQ(m["things"][0]["confidence"].get<double>(), 0.46);
  EXPECT_NEAR(m["things"][0]["position"][0].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(m["things"][0]["position"][1].get<double>(), 3.0, 1e-9);
  // A status the page does not know is said as such, not read past the names.
  plan.steps()[0].status(9);
  EXPECT_EQ(json::parse(plan_message(plan, frame))["steps"][0]["status"], "?");
}

TEST(WebMessages, ThePageGetsAnAnswerToAnythingItSends) {
  EXPECT_EQ(json::parse(answer(R"({"type":"hello"})", 9, "kurt"))["domain"], 9);
  for (const std::string& bad :
       std::vector<std::string>{"not json {", "[1,2]", R"({"type":7})", R"({"type":"explode"})",
                                "\xff\xfe{\"type\":\"\xc3\x28\"}"}) {
    const json reply = json::parse(answer(bad, 9, "kurt"));  // always valid JSON
    EXPECT_EQ(reply["type"], "error") << bad;
    EXPECT_FALSE(reply["message"].get<std::string>().empty());
  }
}

}  // namespace
}  // namespace macsim::web
