#include "learning.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "macsim/images/image_files.h"
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

// The first trials of 1,000 per affordance (generator balanced, K = 2) as affordance_trials
// wrote them: stack seeds 1-300, traverse seeds 1-200 (a traverse row has the cloud's 240 cells).
TEST(Learning, StackabilityAndTraversabilityAreLearnedFromWhatTheRobotSaw) {
  const struct {
    const char* file;
    const char* affordance;
    int rows;
    double at_least;  // held-out accuracy on these rows: stack 89.9 %, traverse 91.8 %
  } cases[] = {{"tests/tools/affordances/stack_trials.csv", "stack", 300, 0.87},
               {"tests/tools/affordances/traverse_trials.csv", "traverse", 200, 0.88}};
  for (const auto& c : cases) {
    const auto sets = datasets(read_csv(source(c.file)));
    ASSERT_EQ(sets.count(c.affordance), 1u) << c.file;
    const Dataset& d = sets.at(c.affordance);
    EXPECT_EQ(d.features.rows, c.rows);
    EXPECT_EQ(d.feature_names, feature_names(*affordance_from_name(c.affordance)));
    const std::vector<std::string>& known = labels(*affordance_from_name(c.affordance));
    EXPECT_EQ(d.classes.size(), known.size()) << c.affordance;  // every label occurs
    const Evaluation e = evaluate(d);
    // The commonest label among the held-out trials, as a share of them.
    std::vector<int> per_class(d.classes.size(), 0);
    for (int row : e.rows)
      ++per_class[static_cast<std::size_t>(d.labels[static_cast<std::size_t>(row)])];
    const double majority =
        *std::max_element(per_class.begin(), per_class.end()) / static_cast<double>(e.tested);
    EXPECT_GE(e.accuracy, c.at_least) << c.affordance;
    EXPECT_GE(e.accuracy, majority + 0.25) << c.affordance;
    // Which shapes it gets wrong: every held-out trial counted once.
    const std::string by_shape = shape_text(d, e);
    EXPECT_NE(by_shape.find("sphere"), std::string::npos) << by_shape;
    EXPECT_EQ(static_cast<int>(e.predicted.size()), e.tested);
  }
}

TEST(Learning, PlotsAreWrittenAndNotBlank) {
  const Dataset lift = datasets(read_csv(kRows)).at("lift");
  macsim::test::TempDir dir("learning_");
  plot_learning_curve(learning_curve(lift), "lift", dir.path() + "/curve.png");
  plot_scatter(lift, "hue", "width_m", dir.path() + "/scatter.png");
  for (const char* f : {"/curve.png", "/scatter.png"}) {
    const cv::Mat image = macsim::images::read_image(dir.path() + f);
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
