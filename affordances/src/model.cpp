#include "macsim/affordances/model.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <opencv2/ml.hpp>
#include <set>

namespace macsim::affordances {

bool held_out(std::uint64_t seed) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return (z ^ (z >> 31)) % 10 < 3;
}

namespace {

constexpr const char* kForestNode = "opencv_ml_rtrees";  // where RTrees::save() writes it
constexpr const char* kInfoNode = "macsim_affordance_model";
constexpr int kTrees = 100;

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

std::vector<std::string> strings(const cv::FileNode& node) {
  std::vector<std::string> out;
  for (const auto& item : node) out.push_back(static_cast<std::string>(item));
  return out;
}

void write_info(cv::FileStorage& fs, const ModelInfo& i) {
  fs << kInfoNode << "{";
  fs << "format_version" << i.format_version << "project_version" << i.project_version;
  fs << "affordance" << i.affordance;
  fs << "features" << "[";
  for (const auto& f : i.features) fs << f;
  fs << "]" << "labels" << "[";
  for (const auto& l : i.labels) fs << l;
  fs << "]";
  fs << "generator" << i.generator << "rows" << i.rows << "seeds" << i.seeds;
  fs << "held_out_accuracy" << i.held_out_accuracy << "held_out_rows" << i.held_out_rows;
  fs << "trees" << i.trees;
  fs << "note"
     << "held_out_accuracy was measured on held_out_rows trials (30 % of the seeds) with a "
        "forest fitted on the others; the forest in this file was then refit on all rows";
  fs << "}";
}

}  // namespace

struct AffordanceModel::Forest {
  cv::Ptr<cv::ml::RTrees> trees;
  mutable std::mutex mutex;  // OpenCV does not promise concurrent predict()
};

AffordanceModel::AffordanceModel(ModelInfo info, std::shared_ptr<const Forest> forest)
    : info_(std::move(info)), forest_(std::move(forest)) {}

const ModelInfo& AffordanceModel::info() const { return info_; }

AffordanceModel AffordanceModel::train(ModelInfo info, const cv::Mat& features,
                                       const std::vector<int>& labels) {
  if (features.type() != CV_32F || features.rows != static_cast<int>(labels.size()) ||
      features.cols != static_cast<int>(info.features.size()) || features.rows == 0)
    throw ModelError("train: " + std::to_string(features.rows) + " rows of " +
                     std::to_string(features.cols) + " features for " +
                     std::to_string(labels.size()) + " labels and " +
                     std::to_string(info.features.size()) + " feature names");
  const std::set<int> seen(labels.begin(), labels.end());
  if (seen.size() < 2)
    throw ModelError("train: the rows of " + info.affordance +
                     " have one label only: nothing to learn");
  for (int l : seen) {
    if (l < 0 || l >= static_cast<int>(info.labels.size()))
      throw ModelError("train: label index " + std::to_string(l) + " has no name");
  }
  auto forest = std::make_shared<Forest>();
  forest->trees = cv::ml::RTrees::create();
  forest->trees->setMaxDepth(12);
  forest->trees->setMinSampleCount(2);
  forest->trees->setCalculateVarImportance(false);
  forest->trees->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER, kTrees, 0));
  cv::theRNG().state = 0x12345678;  // the same forest from the same rows
  forest->trees->train(
      cv::ml::TrainData::create(features, cv::ml::ROW_SAMPLE, cv::Mat(labels, true)));
  info.trees = static_cast<int>(forest->trees->getRoots().size());
  info.format_version = kModelFormatVersion;
  info.project_version = MACSIM_VERSION;
  return AffordanceModel(std::move(info), std::move(forest));
}

void AffordanceModel::save(const std::string& path) const {
  // OpenCV's save() writes the forest, the metadata is appended: YAML only (OpenCV appends to
  // neither compressed nor JSON files). Written beside it and renamed: a failed save leaves
  // the model that was there.
  if (path.size() < 4 || path.compare(path.size() - 4, 4, ".yml") != 0)
    throw ModelError(path + ": a model file ends in .yml");
  const std::string partial = path + ".partial.yml";
  try {
    forest_->trees->save(partial);
    cv::FileStorage fs(partial, cv::FileStorage::APPEND);
    if (!fs.isOpened()) throw ModelError(path + ": cannot be written");
    write_info(fs, info_);
    fs.release();
  } catch (const cv::Exception& e) {
    std::filesystem::remove(partial);
    throw ModelError(path + ": cannot be written: " + e.msg);
  }
  std::error_code ec;
  std::filesystem::rename(partial, path, ec);
  if (ec) {
    std::filesystem::remove(partial);
    throw ModelError(path + ": cannot be written: " + ec.message());
  }
}

AffordanceModel AffordanceModel::load(const std::string& path,
                                      const std::vector<std::string>& expected_features) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw ModelError(path + ": no such model file");
  ModelInfo info;
  auto forest = std::make_shared<Forest>();
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) throw ModelError(path + ": not a model file OpenCV can read");
    const cv::FileNode node = fs[kInfoNode];
    if (node.empty() || !node.isMap())
      throw ModelError(path + ": no " + kInfoNode + " section (not a model affordance_learn wrote)");
    if (node["format_version"].empty() || !node["format_version"].isInt())
      throw ModelError(path + ": no format_version");
    info.format_version = static_cast<int>(node["format_version"]);
    if (info.format_version != kModelFormatVersion)
      throw ModelError(path + ": format version " + std::to_string(info.format_version) +
                       "; this build reads version " + std::to_string(kModelFormatVersion));
    info.project_version = static_cast<std::string>(node["project_version"]);
    info.affordance = static_cast<std::string>(node["affordance"]);
    info.features = strings(node["features"]);
    info.labels = strings(node["labels"]);
    info.generator = static_cast<std::string>(node["generator"]);
    info.rows = static_cast<int>(node["rows"]);
    info.seeds = static_cast<std::string>(node["seeds"]);
    info.held_out_accuracy = static_cast<double>(node["held_out_accuracy"]);
    info.held_out_rows = static_cast<int>(node["held_out_rows"]);
    info.trees = static_cast<int>(node["trees"]);
    if (info.affordance.empty() || info.features.empty() || info.labels.size() < 2)
      throw ModelError(path + ": the affordance, its features or its labels are missing");
    if (!std::isfinite(info.held_out_accuracy) || info.held_out_accuracy < 0 ||
        info.held_out_accuracy > 1)
      throw ModelError(path + ": held_out_accuracy is not a fraction");
    if (fs[kForestNode].empty()) throw ModelError(path + ": no forest (" + kForestNode + ")");
    forest->trees = cv::ml::RTrees::load(path, kForestNode);
  } catch (const cv::Exception& e) {
    throw ModelError(path + ": damaged: " + e.msg);
  }
  const auto& trees = forest->trees;
  if (!trees || !trees->isTrained()) throw ModelError(path + ": damaged: the forest is empty");
  if (trees->getVarCount() != static_cast<int>(info.features.size()))
    throw ModelError(path + ": the forest takes " + std::to_string(trees->getVarCount()) +
                     " features, the file names " + std::to_string(info.features.size()));
  if (static_cast<int>(trees->getRoots().size()) != info.trees)
    throw ModelError(path + ": damaged: " + std::to_string(trees->getRoots().size()) +
                     " trees, the file says " + std::to_string(info.trees));
  for (const auto& split : trees->getSplits()) {
    if (!std::isfinite(split.c) || !std::isfinite(split.quality))
      throw ModelError(path + ": damaged: a split of the forest is not a finite number");
  }
  for (const auto& n : trees->getNodes()) {
    if (!std::isfinite(n.value)) throw ModelError(path + ": damaged: a node is not finite");
    if (n.split < 0 && (n.value < 0 || n.value >= static_cast<double>(info.labels.size())))
      throw ModelError(path + ": damaged: a leaf's label has no name");
  }
  if (!expected_features.empty() && expected_features != info.features)
    throw ModelError(path + ": the model takes the features (" + joined(info.features) +
                     "), the caller computes (" + joined(expected_features) + ")");
  return AffordanceModel(std::move(info), std::move(forest));
}

Prediction AffordanceModel::predict(const std::vector<double>& features) const {
  if (features.size() != info_.features.size())
    throw ModelError(info_.affordance + " model: " + std::to_string(features.size()) +
                     " features given, it takes " + std::to_string(info_.features.size()) +
                     " (" + joined(info_.features) + ")");
  cv::Mat row(1, static_cast<int>(features.size()), CV_32F);
  for (std::size_t i = 0; i < features.size(); ++i) {
    if (!std::isfinite(features[i]) || std::fabs(features[i]) > 3.0e38)
      throw ModelError(info_.affordance + " model: feature " + info_.features[i] + " is " +
                       (std::isnan(features[i]) ? std::string("nan")
                        : features[i] > 0       ? std::string("too large or infinite")
                                                : std::string("too small or -infinite")) +
                       ", not a finite number");
    row.at<float>(0, static_cast<int>(i)) = static_cast<float>(features[i]);
  }
  return vote(row).front();
}

std::vector<Prediction> AffordanceModel::vote(const cv::Mat& rows) const {
  cv::Mat votes;
  {
    std::lock_guard<std::mutex> lock(forest_->mutex);
    forest_->trees->getVotes(rows, votes, 0);
  }
  // Row 0: the labels the votes are for; then a row per sample: its votes per label. The most
  // votes win; a tie goes to the first label.
  std::vector<Prediction> out;
  for (int r = 1; r < votes.rows; ++r) {
    Prediction p;
    double total = 0, best = -1;
    for (int c = 0; c < votes.cols; ++c) {
      const double n = votes.at<int>(r, c);
      total += n;
      if (n > best) best = n, p.label_index = votes.at<int>(0, c);
    }
    if (p.label_index < 0 || p.label_index >= static_cast<int>(info_.labels.size()) || total <= 0)
      throw ModelError(info_.affordance + " model: the forest voted for no known label");
    p.label = info_.labels[static_cast<std::size_t>(p.label_index)];
    p.confidence = best / total;
    out.push_back(std::move(p));
  }
  return out;
}

Prediction AffordanceModel::predict(const std::map<std::string, double>& features) const {
  std::vector<double> ordered;
  ordered.reserve(info_.features.size());
  for (const auto& name : info_.features) {
    const auto at = features.find(name);
    if (at == features.end())
      throw ModelError(info_.affordance + " model: no value for feature " + name);
    ordered.push_back(at->second);
  }
  return predict(ordered);
}

std::vector<int> AffordanceModel::predict_rows(const cv::Mat& rows) const {
  if (rows.type() != CV_32F || rows.cols != static_cast<int>(info_.features.size()))
    throw ModelError(info_.affordance + " model: rows of " + std::to_string(rows.cols) +
                     " features, it takes " + std::to_string(info_.features.size()));
  std::vector<int> labels;
  if (rows.rows == 0) return labels;
  for (const auto& p : vote(rows)) labels.push_back(p.label_index);
  return labels;
}

}  // namespace macsim::affordances
