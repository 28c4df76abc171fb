// A learned affordance model as a file: a random forest (OpenCV ml, its own save() format) with
// what a controller needs to use it (the affordance, the features in order, the labels, where
// the rows came from, the held-out accuracy). find_package(macsim) -> macsim::affordances.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace macsim::affordances {

/// The version of the model file's layout this build writes and reads.
inline constexpr int kModelFormatVersion = 1;

/// Trials held out for testing a learner: 30 % of the seeds, chosen by a hash of the seed (the
/// same seed is held out in every run, whatever else the rows hold).
bool held_out(std::uint64_t seed);

/// A model that cannot be loaded, saved or asked: the message names the file or the feature.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a model file says besides its forest.
struct ModelInfo {
  std::string affordance;             ///< lift, push, climb, stack or traverse
  std::vector<std::string> features;  ///< the forest's inputs, in order
  std::vector<std::string> labels;    ///< the forest's outputs (label index -> name)
  std::string generator;              ///< the trials' generator(s), comma-separated
  int rows = 0;                       ///< trial rows the forest was fitted on
  std::string seeds;                  ///< their seeds as ranges, e.g. "1-300,401-500"
  double held_out_accuracy = 0;       ///< measured before the forest was refit on every row
  int held_out_rows = 0;              ///< trials held out for that measurement
  int trees = 0;                      ///< trees in the forest
  int format_version = kModelFormatVersion;
  std::string project_version;  ///< the version of MACSim-DDS that wrote the file
};

/// A label and how many of the forest's trees voted for it (0..1).
struct Prediction {
  std::string label;
  int label_index = -1;
  double confidence = 0;
};

/// A trained forest and its ModelInfo; cheap to copy, safe to use from several threads.
class AffordanceModel {
 public:
  /// Fits a forest on `features` (CV_32F, a row per trial, columns as info.features) and
  /// `labels` (indices into info.labels; two labels at least). Same rows, same forest.
  static AffordanceModel train(ModelInfo info, const cv::Mat& features,
                               const std::vector<int>& labels);
  /// Reads a model file; with `expected_features`, refuses a model whose features differ.
  static AffordanceModel load(const std::string& path,
                              const std::vector<std::string>& expected_features = {});
  /// Writes the model file (`.yml`); a failed save leaves the file that was there.
  void save(const std::string& path) const;

  /// The label for one trial's features, in info().features order (finite values).
  Prediction predict(const std::vector<double>& features) const;
  /// The same from features by name (every feature of the model; other names are ignored).
  Prediction predict(const std::map<std::string, double>& features) const;
  /// Label indices for many rows at once (CV_32F, one row per trial).
  std::vector<int> predict_rows(const cv::Mat& rows) const;

  const ModelInfo& info() const;

 private:
  struct Forest;
  AffordanceModel(ModelInfo info, std::shared_ptr<const Forest> forest);
  std::vector<Prediction> vote(const cv::Mat& rows) const;
  ModelInfo info_;
  std::shared_ptr<const Forest> forest_;
};

}  // namespace macsim::affordances
