#include "learning.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "support/child_process.h"

namespace affordances {
namespace {

using macsim::test::source;

// 300 lift trials (generator material, seeds 1-300) as affordance_trials wrote them.
const std::string kRows = source("tests/tools/affordances/lift_trials.csv");

TEST(Learning, HeldOutTrialsAreAboutThirtyPercentChosenBySeed) {
  int held = 0;
  for (uint64_t s = 1; s <= 10000; ++s) held += held_out(s);
  EXPECT_NEAR(held / 10000.0, 0.3, 0.02);
  EXPECT_EQ(held_out(17), held_out(17));
}

TEST(Learning, LiftabilityIsLearnedFromWhatTheRobotSaw) {
  const auto sets = datasets(read_csv(kRows));
  ASSERT_EQ(sets.count("lift"), 1u);
  const Dataset& lift = sets.at("lift");
  ASSERT_EQ(lift.classes, (std::vector<std::string>{"liftable", "not_liftable"}));
  EXPECT_EQ(lift.features.rows, 300);
  const Evaluation e = evaluate(lift);
  EXPECT_GT(e.tested, 60);
  // Better than always answering the commoner label, and at least 95 % right (99 % here).
  const int liftable = static_cast<int>(std::count(lift.labels.begin(), lift.labels.end(), 0));
  const double majority = std::max(liftable, 300 - liftable) / 300.0;
  EXPECT_GE(e.accuracy, 0.95);
  EXPECT_GT(e.accuracy, majority);
  EXPECT_EQ(cv::sum(e.confusion)[0], e.tested);
  // The same rows give the same forest.
  EXPECT_EQ(evaluate(lift).accuracy, e.accuracy);
  const auto curve = learning_curve(lift);
  ASSERT_GE(curve.size(), 4u);
  EXPECT_EQ(curve.back().first, e.trained);
  EXPECT_GE(curve.back().second, curve.front().second);
}

TEST(Learning, PlotsAreWrittenAndNotBlank) {
  const Dataset lift = datasets(read_csv(kRows)).at("lift");
  macsim::test::TempDir dir("learning_");
  plot_learning_curve(learning_curve(lift), "lift", dir.path() + "/curve.png");
  plot_scatter(lift, "hue", "width_m", dir.path() + "/scatter.png");
  for (const char* f : {"/curve.png", "/scatter.png"}) {
    const cv::Mat image = cv::imread(dir.path() + f);
    ASSERT_FALSE(image.empty()) << f;
    cv::Scalar mean, deviation;
    cv::meanStdDev(image, mean, deviation);
    EXPECT_GT(deviation[0], 10.0) << f;
  }
  EXPECT_THROW(plot_scatter(lift, "hue", "no_such_feature", dir.path() + "/x.png"),
               std::runtime_error);
}

TEST(Learning, FeaturesCanBeChosenAndAMissingOneIsNamed) {
  const auto only_colour = datasets(read_csv(kRows), {"r", "g", "b"});
  EXPECT_EQ(only_colour.at("lift").features.cols, 3);
  try {
    datasets(read_csv(kRows), {"r", "weight"});
    FAIL() << "an unknown feature was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("weight"), std::string::npos);
  }
}

}  // namespace
}  // namespace affordances
