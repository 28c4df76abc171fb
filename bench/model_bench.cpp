// Learned affordance models (macsim::affordances): each committed trial file's model trained,
// saved and loaded as affordance_learn and a controller do; its file size, load time and the
// cost of one prediction beside the baseline of OpenCV's own RTrees::predict on the same forest
// and row, measured in the same run. `name value unit` lines.
//   bench_models [PREDICTIONS]   (default 20000; from the repository root)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <opencv2/ml.hpp>
#include <string>
#include <vector>

#include "learning.h"
#include "macsim/affordances/model.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  namespace af = macsim::affordances;
  int predictions = 20000;
  if (argc > 2) {
    std::fprintf(stderr, "usage: bench_models [PREDICTIONS]\n");
    return 2;
  }
  if (argc == 2) {
    const std::string arg = argv[1];
    if (arg == "--help" || arg == "-h") {
      std::printf("usage: bench_models [PREDICTIONS]: affordance model files, their load and "
                  "predict cost beside OpenCV's RTrees::predict (run from the repository root)\n");
      return 0;
    }
    char* end = nullptr;
    const long n = std::strtol(arg.c_str(), &end, 10);
    if (arg.empty() || *end || n < 1 || n > 100000000) {
      std::fprintf(stderr, "bench_models: PREDICTIONS must be positive, not '%s'\n", arg.c_str());
      return 2;
    }
    predictions = static_cast<int>(n);
  }
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("bench_models_" + std::to_string(getpid())))
          .string();
  std::filesystem::create_directories(dir);
  int status = 0;
  for (const char* affordance : {"lift", "stack", "traverse"}) {
    const std::string rows = std::string("tests/tools/affordances/") + affordance + "_trials.csv";
    try {
      const auto data = affordances::datasets(affordances::read_csv(rows)).at(affordance);
      const std::string file = dir + "/" + affordance + ".yml";
      affordances::fit(data, affordances::evaluate(data)).save(file);
      std::printf("model_file_%s %.0f KB\n", affordance,
                  static_cast<double>(std::filesystem::file_size(file)) / 1024.0);
      auto start = Clock::now();
      const auto model = af::AffordanceModel::load(file);
      std::printf("model_load_%s %.1f ms\n", affordance, 1e3 * seconds_since(start));
      const auto raw = cv::ml::RTrees::load(file, "opencv_ml_rtrees");
      std::vector<std::vector<double>> samples;
      for (int r = 0; r < data.features.rows; ++r) {
        std::vector<double> row;
        for (int k = 0; k < data.features.cols; ++k) row.push_back(data.features.at<float>(r, k));
        samples.push_back(row);
      }
      // The baseline: OpenCV's predict of the same row (its majority vote, no confidence).
      double sink = 0;
      start = Clock::now();
      for (int i = 0; i < predictions; ++i)
        sink += raw->predict(data.features.row(i % data.features.rows));
      const double baseline = seconds_since(start) / predictions;
      start = Clock::now();
      for (int i = 0; i < predictions; ++i)
        sink += model.predict(samples[static_cast<std::size_t>(i) % samples.size()]).confidence;
      const double ours = seconds_since(start) / predictions;
      std::printf("model_predict_%s %.2f us\n", affordance, 1e6 * ours);
      std::printf("rtrees_predict_%s %.2f us\n", affordance, 1e6 * baseline);
      std::printf("model_predict_ratio_%s %.2f x\n", affordance, ours / baseline);
      if (sink == -1) std::printf("\n");  // keeps the loops
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_models: %s: %s\n", rows.c_str(), e.what());
      status = 1;
    }
  }
  std::filesystem::remove_all(dir);
  return status;
}
