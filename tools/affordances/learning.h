// Learning an affordance from trial rows: a random forest (OpenCV ml) per affordance on the
// perceived features, held-out accuracy and confusion matrix, a learning curve, and plots.
#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "macsim/affordances/model.h"
#include "trial_record.h"

namespace affordances {

/// The rows of one affordance as features and labels.
struct Dataset {
  std::string affordance;
  std::vector<std::string> feature_names;
  cv::Mat features;                  ///< CV_32F, one row per trial
  std::vector<int> labels;           ///< index into classes
  std::vector<std::string> classes;  ///< sorted label names
  std::vector<uint64_t> seeds;
  std::vector<std::string> shapes;  ///< each trial's shape column (empty when the rows lack it)
  std::vector<std::string> generators;  ///< the generators the rows came from, sorted
};

/// One Dataset per affordance in the table, with the named feature columns (empty: every
/// perceived feature). Throws std::runtime_error naming a missing column.
std::map<std::string, Dataset> datasets(const CsvTable& table,
                                        const std::vector<std::string>& features = {});

/// Trials held out for testing (model.h): 30 % of the seeds, by a hash of the seed.
using macsim::affordances::held_out;

struct Evaluation {
  int trained = 0, tested = 0;
  double accuracy = 0;               ///< on the held-out trials
  cv::Mat confusion;                 ///< CV_32S, rows: true class, columns: predicted
  std::vector<int> rows, predicted;  ///< the held-out trials (rows of the Dataset), predictions
};

/// Trains a random forest on the first `max_train` training trials (all when < 0) and tests it
/// on every held-out trial.
Evaluation evaluate(const Dataset& data, int max_train = -1);

/// The forest refit on every row of `data`, with what the file says of it (`held_out`: the
/// evaluation made before). Throws macsim::affordances::ModelError with one label only.
macsim::affordances::AffordanceModel fit(const Dataset& data, const Evaluation& held_out);

/// Seeds as ranges, sorted: "1-300,401,403-410".
std::string seed_ranges(std::vector<uint64_t> seeds);

/// Accuracy against the number of training trials.
std::vector<std::pair<int, double>> learning_curve(const Dataset& data);

/// The learning curve as a PNG.
void plot_learning_curve(const std::vector<std::pair<int, double>>& curve, const std::string& title,
                         const std::string& file);
/// Two features against each other, each trial a dot coloured by its label, as a PNG.
void plot_scatter(const Dataset& data, const std::string& x_feature, const std::string& y_feature,
                  const std::string& file);

/// The confusion matrix as text.
std::string confusion_text(const Dataset& data, const Evaluation& evaluation);
/// Held-out accuracy per shape (what the learner gets wrong), as text; empty without shapes.
std::string shape_text(const Dataset& data, const Evaluation& evaluation);

}  // namespace affordances
