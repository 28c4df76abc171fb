// One perception: a controller that computes an affordance's features from what the robot saw
// (the library's perceive() and features() on the stereo pair, the sweep and the cloud, as a
// controller gets them from the robot's topics) finds exactly the row affordance_trials wrote
// for that trial, as the rows' text has it (%.9g), for the camera and sweep features (lift) and
// the cloud's grid and corridor (traverse).
#include <gtest/gtest.h>

#include <cstdio>

#include "macsim/affordances/perception.h"
#include "support/child_process.h"
#include "support/test_domain.h"
#include "trial_record.h"

namespace macsim::affordances {
namespace {

using namespace std::chrono_literals;
using macsim::test::bin;
using macsim::test::ChildProcess;
using macsim::test::TempDir;

std::string text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

TEST(PerceptionParity, AControllerComputesEachTrialsRowFromWhatTheTrialSaw) {
  TempDir dir("perception_parity_");
  const struct {
    const char* affordance;
    const char* generator;
    const char* seed;
    const char* trials;
  } cases[] = {{"lift", "material", "5", "2"}, {"traverse", "balanced", "7", "2"}};
  for (const auto& c : cases) {
    const std::string csv = dir.path() + "/" + c.affordance + ".csv";
    ChildProcess trials({bin("affordance_trials"), "--domain",
                         std::to_string(macsim::test::unique_test_domain()), "--affordance",
                         c.affordance, "--generator", c.generator, "--seed", c.seed, "--trials",
                         c.trials, "--out", csv, "--keep-inputs", dir.path() + "/inputs",
                         "--logs", dir.path() + "/logs"});
    ASSERT_EQ(trials.wait_for_exit(120s), 0) << trials.output();
    const auto table = ::affordances::read_csv(csv);
    ASSERT_EQ(table.rows.size(), 2u) << c.affordance;
    const auto affordance = *affordance_from_name(c.affordance);
    const auto& names = feature_names(affordance);
    for (const auto& row : table.rows) {
      const std::string seed = row[*table.column("seed")];
      const SensorInputs inputs =
          load_inputs(dir.path() + "/inputs", std::string(c.affordance) + "_" + seed);
      ASSERT_TRUE(inputs.frame && inputs.scan) << c.affordance << " " << seed;
      EXPECT_EQ(inputs.cloud.has_value(), affordance == Affordance::Traverse);
      const auto values = features(perceive(inputs), affordance);
      ASSERT_EQ(values.size(), names.size());
      int nonzero = 0;
      for (std::size_t i = 0; i < names.size(); ++i) {
        const auto column = table.column(names[i]);
        ASSERT_TRUE(column) << names[i];
        EXPECT_EQ(text(values[i]), row[*column]) << c.affordance << " seed " << seed << " "
                                                 << names[i];
        nonzero += values[i] != 0;
      }
      // It saw something: most features are not zero.
      EXPECT_GT(nonzero, static_cast<int>(names.size()) / 2) << c.affordance << " " << seed;
    }
  }
}

TEST(PerceptionParity, InputsThatCannotBeReadAreRefusedNamingTheFile) {
  TempDir dir("perception_inputs_");
  try {
    load_inputs(dir.path(), "absent");
    FAIL() << "loaded nothing";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir.path() + "/absent.yml.gz"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace macsim::affordances
