// affordance_learn: learns each affordance in a trial CSV (affordance_trials --out) from the
// perceived features with a random forest (OpenCV ml); prints held-out accuracy and the
// confusion matrix, writes a learning curve and a feature scatter per affordance as PNGs, and
// with --save-model the model a controller loads (macsim/affordances/model.h).
#include <filesystem>
#include <iostream>
#include <sstream>

#include "learning.h"
#include "macsim/affordances/perception.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"

int main(int argc, char** argv) {
  using namespace affordances;
  std::string in, out, feature_list, model_dir;
  double min_accuracy = 0;
  macsim::dds::CommandLine cli(
      "affordance_learn",
      "Learns each affordance in a trial CSV from what the robot perceived (a random forest, "
      "OpenCV ml): 30 % of the trials (by seed) are held out for testing. Prints accuracy and "
      "the confusion matrix; writes DIR/<affordance>_learning_curve.png and "
      "DIR/<affordance>_scatter.png.\nExit 0: learned; 1: an accuracy below --min-accuracy; "
      "2: usage, unreadable rows or a model that cannot be written.");
  cli.option("in", "FILE.csv", "trial rows (affordance_trials --out)", &in);
  cli.option("out", "DIR", "where the plots go (created)", &out);
  cli.option("features", "A,B,...",
             "learn from these perceived features only (default all: r,g,b,hue,area_px,...); a "
             "sensor's group stands for its features: camera, sweep, top, cloud, shape",
             &feature_list);
  cli.option("min-accuracy", "FRACTION", "exit 1 when an affordance is learned less well",
             &min_accuracy);
  cli.option("save-model", "DIR",
             "write DIR/<affordance>.yml per affordance: the forest refit on every row, its "
             "features, labels, rows, seeds and held-out accuracy (created)",
             &model_dir);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (in.empty() || (out.empty() && model_dir.empty())) {
    macsim::log::error(
        "affordance_learn: say which rows and where the plots or models go: --in FILE.csv "
        "--out DIR and/or --save-model DIR (see --help)");
    return 2;
  }
  std::vector<std::string> features;
  std::stringstream list(feature_list);
  for (std::string f; std::getline(list, f, ',');) {
    // A sensor's group stands for its features (e.g. cloud: what a navigator has).
    if (const auto* group = macsim::affordances::feature_group(f))
      features.insert(features.end(), group->begin(), group->end());
    else
      features.push_back(f);
  }

  std::map<std::string, Dataset> sets;
  try {
    const CsvTable table = read_csv(in);  // its errors name the file and line
    try {
      sets = datasets(table, features);
    } catch (const std::exception& e) {
      macsim::log::error("affordance_learn: {}: {}", in, e.what());
      return 2;
    }
  } catch (const std::exception& e) {
    macsim::log::error("affordance_learn: {}", e.what());
    return 2;
  }
  if (sets.empty()) {
    macsim::log::error("affordance_learn: {} has no trial rows", in);
    return 2;
  }
  std::error_code made;
  for (const auto& dir : {out, model_dir}) {
    if (dir.empty()) continue;
    std::filesystem::create_directories(dir, made);
    if (made) {
      macsim::log::error("affordance_learn: cannot create {}: {}", dir, made.message());
      return 2;
    }
  }
  bool good = true;
  for (const auto& [affordance, data] : sets) {
    const Evaluation e = evaluate(data);
    std::printf("%s: %d trials (%d to train, %d held out), held-out accuracy %.1f %%\n",
                affordance.c_str(), data.features.rows, e.trained, e.tested, 100 * e.accuracy);
    std::printf("%s", confusion_text(data, e).c_str());
    std::printf("%s", shape_text(data, e).c_str());
    if (!model_dir.empty()) {
      const std::string file = model_dir + "/" + affordance + ".yml";
      try {
        fit(data, e).save(file);
      } catch (const std::exception& err) {
        macsim::log::error("affordance_learn: {}", err.what());
        return 2;
      }
      std::printf("  model: %s (%.0f KB; the forest refit on all %d rows)\n", file.c_str(),
                  static_cast<double>(std::filesystem::file_size(file)) / 1024.0,
                  data.features.rows);
    }
    if (out.empty()) {
      if (e.accuracy < min_accuracy) good = false;
      continue;
    }
    const auto curve = learning_curve(data);
    std::printf("  learning curve:");
    for (const auto& [n, accuracy] : curve) std::printf(" %d:%.1f%%", n, 100 * accuracy);
    std::printf("\n");
    // The scatter's axes: what matters most to each affordance, as the robot saw it.
    const bool all = features.empty();
    std::string x = all ? "hue" : data.feature_names[0];
    std::string y = all                             ? "width_m"
                    : data.feature_names.size() > 1 ? data.feature_names[1]
                                                    : data.feature_names[0];
    if (all && affordance == "push") x = "fill";
    if (all && affordance == "climb") x = "laser_slope", y = "laser_height";
    if (all && affordance == "stack") x = "fill", y = "top_length";
    if (all && affordance == "traverse") x = "free_width", y = "corridor_height";
    try {
      plot_learning_curve(curve, affordance + ": held-out accuracy against training trials",
                          out + "/" + affordance + "_learning_curve.png");
      plot_scatter(data, x, y, out + "/" + affordance + "_scatter.png");
    } catch (const std::exception& err) {
      macsim::log::error("affordance_learn: {}", err.what());
      return 2;
    }
    std::printf("  plots: %s/%s_learning_curve.png, %s/%s_scatter.png\n", out.c_str(),
                affordance.c_str(), out.c_str(), affordance.c_str());
    if (e.accuracy < min_accuracy) good = false;
  }
  return good ? 0 : 1;
}
