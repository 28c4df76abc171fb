#include "trial_record.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "support/child_process.h"

namespace affordances {
namespace {

std::size_t fields(const std::string& line) {
  return std::count(line.begin(), line.end(), ',') + 1;
}

TEST(TrialRecord, ARowHasAFieldForEveryColumnAndReadsBack) {
  TrialRecord r;
  r.spec = make_trial(Affordance::Push, Generator::Material, 7);
  r.outcome.label = "rolled";
  r.outcome.moved = 0.25;
  r.percept.seen = true;
  r.percept.hue = 12.5;
  r.final_hash = 0xabcdef;
  r.instance = 2;
  EXPECT_EQ(fields(csv_header()), fields(csv_row(r)));
  macsim::test::TempDir dir("trial_record_");
  const std::string path = dir.path() + "/rows.csv";
  std::ofstream(path) << csv_header() << "\n" << csv_row(r) << "\n";
  const CsvTable t = read_csv(path);
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0][*t.column("affordance")], "push");
  EXPECT_EQ(t.rows[0][*t.column("seed")], "7");
  EXPECT_EQ(t.rows[0][*t.column("label")], "rolled");
  EXPECT_EQ(t.rows[0][*t.column("hue")], "12.5");
  EXPECT_EQ(t.rows[0][*t.column("final_hash")], "0000000000abcdef");
  EXPECT_EQ(t.rows[0][*t.column("instance")], "2");
  EXPECT_EQ(t.columns.back(), "wall_time");
  EXPECT_FALSE(t.column("no such column"));
}

TEST(TrialRecord, StackAndTraverseRowsCarryTheirOwnFeaturesAndMeasures) {
  for (auto a : {Affordance::Stack, Affordance::Traverse}) {
    TrialRecord r;
    r.spec = make_trial(a, Generator::Balanced, 3);
    r.outcome.label = labels(a).front();
    r.outcome.passed = 0.125;
    r.outcome.settle = -0.002;
    r.percept.grid.assign(10, 1.5);  // fewer cells than the grid: the rest are zero
    EXPECT_EQ(fields(csv_header(a)), fields(csv_row(r))) << name(a);
    EXPECT_NE(csv_header(a), csv_header(Affordance::Lift));
    macsim::test::TempDir dir("trial_record_");
    const std::string path = dir.path() + "/rows.csv";
    std::ofstream(path) << csv_header(a) << "\n" << csv_row(r) << "\n";
    const CsvTable t = read_csv(path);
    ASSERT_EQ(t.rows.size(), 1u);
    for (const auto& feature : feature_names(a)) EXPECT_TRUE(t.column(feature)) << feature;
    if (a == Affordance::Stack) {
      EXPECT_EQ(t.rows[0][*t.column("carried_shape")], name(r.spec.carried.shape));
      EXPECT_EQ(t.rows[0][*t.column("settle")], "-0.002");
    } else {
      EXPECT_EQ(t.rows[0][*t.column("cell_0_0_near")], "1.5");
      EXPECT_EQ(t.rows[0][*t.column("cell_7_5_slope")], "0");
      EXPECT_EQ(t.rows[0][*t.column("passed")], "0.125");
      EXPECT_EQ(t.rows[0][*t.column("fixed")], r.spec.fixed ? "1" : "0");
    }
    EXPECT_EQ(t.columns.back(), "wall_time");
  }
  EXPECT_EQ(labels(Affordance::Stack),
            (std::vector<std::string>{"stacked", "slid_off", "toppled"}));
}

TEST(TrialRecord, ARowCutShortAtTheEndIsDroppedOneInTheMiddleIsAnError) {
  TrialRecord r;
  r.spec = make_trial(Affordance::Lift, Generator::Material, 1);
  r.outcome.label = "liftable";
  macsim::test::TempDir dir("trial_record_");
  const std::string path = dir.path() + "/rows.csv";
  const std::string row = csv_row(r);
  std::ofstream(path) << csv_header() << "\n" << row << "\n" << row.substr(0, 30);
  EXPECT_EQ(read_csv(path).rows.size(), 1u);
  std::ofstream(path) << csv_header() << "\n" << row.substr(0, 30) << "\n" << row << "\n";
  try {
    read_csv(path);
    FAIL() << "a short row in the middle was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_csv(dir.path() + "/missing.csv"), std::runtime_error);
}

}  // namespace
}  // namespace affordances
