// Affordance models as files: the forest affordance_learn saves is the forest a controller
// loads (the same predictions on the committed trial rows), the file says what the model is,
// and a missing, damaged, foreign or non-finite file is refused naming the file and the fault.
#include "macsim/affordances/model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>

#include "learning.h"
#include "support/child_process.h"

namespace macsim::affordances {
namespace {

using macsim::test::source;
using macsim::test::TempDir;

struct Fitted {
  ::affordances::Dataset data;
  AffordanceModel model;
};

Fitted fitted(const std::string& rows, const std::string& affordance) {
  auto sets = ::affordances::datasets(::affordances::read_csv(source(rows)));
  auto data = sets.at(affordance);
  const auto held_out = ::affordances::evaluate(data);
  return {data, ::affordances::fit(data, held_out)};
}

std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The message of the ModelError that `load` throws, or "" when it loads.
std::string refusal(const std::string& path, const std::vector<std::string>& features = {}) {
  try {
    AffordanceModel::load(path, features);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(AffordanceModel, SavedAndLoadedPredictsAsTheModelInMemoryOnTheCommittedRows) {
  TempDir dir("affordance_model_");
  const struct {
    const char* rows;
    const char* affordance;
  } cases[] = {{"tests/tools/affordances/lift_trials.csv", "lift"},
               {"tests/tools/affordances/stack_trials.csv", "stack"},
               {"tests/tools/affordances/traverse_trials.csv", "traverse"}};
  for (const auto& c : cases) {
    const Fitted f = fitted(c.rows, c.affordance);
    const std::string file = dir.path() + "/" + c.affordance + ".yml";
    f.model.save(file);
    const AffordanceModel loaded = AffordanceModel::load(file, f.data.feature_names);
    ASSERT_EQ(loaded.predict_rows(f.data.features), f.model.predict_rows(f.data.features))
        << c.affordance;
    int right = 0;
    for (int r = 0; r < f.data.features.rows; ++r) {
      std::vector<double> row;
      for (int k = 0; k < f.data.features.cols; ++k) row.push_back(f.data.features.at<float>(r, k));
      const Prediction in_memory = f.model.predict(row), from_file = loaded.predict(row);
      EXPECT_EQ(from_file.label, in_memory.label) << c.affordance << " row " << r;
      EXPECT_EQ(from_file.confidence, in_memory.confidence) << c.affordance << " row " << r;
      EXPECT_GE(from_file.confidence, 1.0 / static_cast<double>(f.data.classes.size()));
      EXPECT_LE(from_file.confidence, 1.0);
      right += from_file.label_index == f.data.labels[static_cast<std::size_t>(r)];
    }
    // Refit on every row, the forest knows its own rows well.
    EXPECT_GT(right, f.data.features.rows * 9 / 10) << c.affordance;
  }
}

TEST(AffordanceModel, TheFileSaysWhatTheModelIsAndWhereItsRowsCameFrom) {
  TempDir dir("affordance_model_");
  const Fitted f = fitted("tests/tools/affordances/lift_trials.csv", "lift");
  const std::string file = dir.path() + "/lift.yml";
  f.model.save(file);
  const ModelInfo info = AffordanceModel::load(file).info();
  EXPECT_EQ(info.affordance, "lift");
  EXPECT_EQ(info.features, f.data.feature_names);
  EXPECT_EQ(info.labels, (std::vector<std::string>{"liftable", "not_liftable"}));
  EXPECT_EQ(info.generator, "material");
  EXPECT_EQ(info.rows, 300);
  EXPECT_EQ(info.seeds, "1-300");
  EXPECT_EQ(info.held_out_accuracy, ::affordances::evaluate(f.data).accuracy);
  EXPECT_GT(info.held_out_rows, 60);
  EXPECT_EQ(info.trees, 100);
  EXPECT_EQ(info.format_version, kModelFormatVersion);
  EXPECT_FALSE(info.project_version.empty());
  // OpenCV's own format, and the note that the forest was refit on all rows.
  const std::string text = text_of(file);
  EXPECT_NE(text.find("opencv_ml_rtrees:"), std::string::npos);
  EXPECT_NE(text.find("refit on all rows"), std::string::npos);
  // Well under the 5 MB a model may take.
  EXPECT_LT(std::filesystem::file_size(file), 5u << 20);
}

TEST(AffordanceModel, PredictsFromFeaturesByNameAndRefusesMissingOrNonFiniteValues) {
  const Fitted f = fitted("tests/tools/affordances/lift_trials.csv", "lift");
  std::map<std::string, double> named;
  std::vector<double> row;
  for (int k = 0; k < f.data.features.cols; ++k) {
    named[f.data.feature_names[static_cast<std::size_t>(k)]] = f.data.features.at<float>(0, k);
    row.push_back(f.data.features.at<float>(0, k));
  }
  named["not_a_feature"] = 1;  // ignored: a controller may pass all it perceived
  EXPECT_EQ(f.model.predict(named).label, f.model.predict(row).label);

  auto refused = [&](auto&& call) -> std::string {
    try {
      call();
    } catch (const ModelError& e) {
      return e.what();
    }
    return "";
  };
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), -1e308}) {
    auto with_bad = row;
    with_bad[3] = bad;
    EXPECT_NE(refused([&] { f.model.predict(with_bad); }).find("feature hue"), std::string::npos)
        << bad;
  }
  auto missing = named;
  missing.erase("laser_slope");
  EXPECT_NE(refused([&] { f.model.predict(missing); }).find("laser_slope"), std::string::npos);
  row.pop_back();
  EXPECT_NE(refused([&] { f.model.predict(row); }).find("13 features given, it takes 14"),
            std::string::npos);
}

TEST(AffordanceModel, LoadingRefusesEachBadFileNamingTheFileAndTheFault) {
  TempDir dir("affordance_model_");
  const Fitted f = fitted("tests/tools/affordances/lift_trials.csv", "lift");
  const std::string good = dir.path() + "/lift.yml";
  f.model.save(good);
  const std::string text = text_of(good);
  auto written = [&](const std::string& name, const std::string& content) {
    const std::string path = dir.path() + "/" + name;
    std::ofstream(path) << content;
    return path;
  };
  auto expect_refused = [&](const std::string& path, const std::string& fault,
                            const std::vector<std::string>& features = {}) {
    const std::string message = refusal(path, features);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(fault), std::string::npos) << fault << ": " << message;
  };
  ASSERT_EQ(refusal(good), "");

  expect_refused(dir.path() + "/absent.yml", "no such model file");
  // Saved as YAML only; a failed save leaves the model that was there.
  try {
    f.model.save(dir.path() + "/lift.json");
    ADD_FAILURE() << "saved as JSON";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("ends in .yml"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/lift.json"));
  EXPECT_THROW(f.model.save(dir.path() + "/no_such_folder/lift.yml"), ModelError);
  EXPECT_EQ(refusal(good), "");
  // The forest cut in the middle, its metadata kept.
  const auto section = text.find("macsim_affordance_model");
  ASSERT_NE(section, std::string::npos);
  expect_refused(written("cut.yml", text.substr(0, section / 2) + "\n" + text.substr(section)),
                 "damaged");
  expect_refused(written("garbage.yml", "%YAML:1.0\n---\n{{{ not yaml"), "damaged");
  expect_refused(written("forest_only.yml", text.substr(0, text.find("macsim_affordance_model"))),
                 "no macsim_affordance_model section");
  expect_refused(
      written("version.yml", std::regex_replace(text, std::regex("format_version: 1"),
                                                "format_version: 2")),
      "format version 2; this build reads version 1");
  auto other = f.data.feature_names;
  std::swap(other[0], other[1]);
  expect_refused(good, "the model takes the features (r,g,b,", other);
  expect_refused(written("accuracy.yml", std::regex_replace(text, std::regex("held_out_accuracy: [^\n]*"),
                                                            "held_out_accuracy: .Nan")),
                 "held_out_accuracy is not a fraction");
  // A split's threshold that is not a number (the forest's own values are checked too).
  const std::string bad_split = std::regex_replace(text, std::regex("le:[-+.0-9e]+"), "le:.Nan",
                                                   std::regex_constants::format_first_only);
  ASSERT_NE(bad_split, text);
  expect_refused(written("split.yml", bad_split), "not a finite number");
  std::string fewer_trees = std::regex_replace(text, std::regex("\n   trees: 100"), "\n   trees: 99");
  ASSERT_NE(fewer_trees, text);
  expect_refused(written("trees.yml", fewer_trees), "99");
}

}  // namespace
}  // namespace macsim::affordances
