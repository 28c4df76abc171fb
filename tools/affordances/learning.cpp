#include "learning.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>

#include "macsim/images/image_files.h"

namespace affordances {

namespace {

/// Label colours of the plots (BGR): first class green, then red, blue, orange.
const cv::Scalar kClassColours[] = {{60, 170, 40}, {40, 40, 220}, {220, 120, 30}, {0, 150, 255}};

}  // namespace

std::map<std::string, Dataset> datasets(const CsvTable& table,
                                        const std::vector<std::string>& features) {
  std::vector<std::string> names = features;
  const auto affordance = table.column("affordance");
  if (names.empty()) {  // every perceived feature of the rows' affordance
    Affordance a = Affordance::Lift;
    if (affordance && !table.rows.empty()) {
      if (auto named = affordance_from_name(table.rows.front()[*affordance])) a = *named;
    }
    names = feature_names(a);
  }
  std::vector<std::size_t> columns;
  for (const auto& n : names) {
    const auto c = table.column(n);
    if (!c) throw std::runtime_error("no feature column '" + n + "' in the trial rows");
    columns.push_back(*c);
  }
  const auto label = table.column("label"), seed = table.column("seed"),
             shape = table.column("shape"), generator = table.column("generator");
  if (!affordance || !label || !seed)
    throw std::runtime_error("the rows lack the affordance, label or seed column");

  std::map<std::string, std::set<std::string>> classes;
  for (const auto& row : table.rows) classes[row[*affordance]].insert(row[*label]);
  std::map<std::string, Dataset> out;
  for (const auto& [name, labels] : classes) {
    Dataset& d = out[name];
    d.affordance = name;
    d.feature_names = names;
    d.classes.assign(labels.begin(), labels.end());
  }
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const auto& row = table.rows[r];
    // A field that is not a number is named by its row (2 = the first after the header).
    auto number = [&](std::size_t column) {
      const std::string& field = row[column];
      char* end = nullptr;
      const double v = std::strtod(field.c_str(), &end);
      if (field.empty() || *end)
        throw std::runtime_error("row " + std::to_string(r + 2) + ", column " +
                                 table.columns[column] + ": '" + field + "' is not a number");
      return v;
    };
    Dataset& d = out[row[*affordance]];
    cv::Mat sample(1, static_cast<int>(columns.size()), CV_32F);
    for (std::size_t i = 0; i < columns.size(); ++i)
      sample.at<float>(0, static_cast<int>(i)) = static_cast<float>(number(columns[i]));
    d.features.push_back(sample);
    d.labels.push_back(static_cast<int>(std::find(d.classes.begin(), d.classes.end(), row[*label]) -
                                        d.classes.begin()));
    d.seeds.push_back(static_cast<uint64_t>(number(*seed)));
    if (shape) d.shapes.push_back(row[*shape]);
    if (generator && std::find(d.generators.begin(), d.generators.end(), row[*generator]) ==
                         d.generators.end()) {
      d.generators.push_back(row[*generator]);
      std::sort(d.generators.begin(), d.generators.end());
    }
  }
  return out;
}

Evaluation evaluate(const Dataset& data, int max_train) {
  cv::Mat train_x, test_x;
  std::vector<int> train_y, test_y;
  Evaluation e;
  for (int i = 0; i < data.features.rows; ++i) {
    if (held_out(data.seeds[i])) {
      test_x.push_back(data.features.row(i));
      test_y.push_back(data.labels[i]);
      e.rows.push_back(i);
    } else if (max_train < 0 || static_cast<int>(train_y.size()) < max_train) {
      train_x.push_back(data.features.row(i));
      train_y.push_back(data.labels[i]);
    }
  }
  const int n = static_cast<int>(data.classes.size());
  e.confusion = cv::Mat::zeros(n, n, CV_32S);
  e.trained = static_cast<int>(train_y.size());
  e.tested = static_cast<int>(test_y.size());
  if (train_y.empty() || test_y.empty()) return e;
  std::vector<int> predicted(test_y.size(), train_y[0]);
  if (std::set<int>(train_y.begin(), train_y.end()).size() > 1) {
    // The forest a saved model has (macsim::affordances), fitted on the training trials only.
    macsim::affordances::ModelInfo info;
    info.affordance = data.affordance;
    info.features = data.feature_names;
    info.labels = data.classes;
    predicted = macsim::affordances::AffordanceModel::train(info, train_x, train_y)
                    .predict_rows(test_x);
  }
  e.predicted = predicted;
  int right = 0;
  for (std::size_t i = 0; i < test_y.size(); ++i) {
    ++e.confusion.at<int>(test_y[i], predicted[i]);
    right += test_y[i] == predicted[i];
  }
  e.accuracy = static_cast<double>(right) / static_cast<double>(test_y.size());
  return e;
}

macsim::affordances::AffordanceModel fit(const Dataset& data, const Evaluation& held_out) {
  macsim::affordances::ModelInfo info;
  info.affordance = data.affordance;
  info.features = data.feature_names;
  info.labels = data.classes;
  for (const auto& g : data.generators) info.generator += (info.generator.empty() ? "" : ",") + g;
  info.rows = data.features.rows;
  info.seeds = seed_ranges(data.seeds);
  info.held_out_accuracy = held_out.accuracy;
  info.held_out_rows = held_out.tested;
  return macsim::affordances::AffordanceModel::train(info, data.features, data.labels);
}

std::string seed_ranges(std::vector<uint64_t> seeds) {
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  std::string out;
  for (std::size_t i = 0; i < seeds.size();) {
    std::size_t j = i;
    while (j + 1 < seeds.size() && seeds[j + 1] == seeds[j] + 1) ++j;
    out += (out.empty() ? "" : ",") + std::to_string(seeds[i]);
    if (j > i) out += "-" + std::to_string(seeds[j]);
    i = j + 1;
  }
  return out;
}

std::vector<std::pair<int, double>> learning_curve(const Dataset& data) {
  int training = 0;
  for (uint64_t s : data.seeds) training += !held_out(s);
  std::vector<std::pair<int, double>> curve;
  for (int n :
       {5, 10, 20, 35, 50, 75, 100, 150, 200, 300, 500, 700, 1000, 1500, 2000, 3000, 5000}) {
    if (n > training) break;
    curve.emplace_back(n, evaluate(data, n).accuracy);
  }
  if (curve.empty() || curve.back().first != training)
    curve.emplace_back(training, evaluate(data).accuracy);
  return curve;
}

namespace {

/// A white canvas with a framed plot area, axis labels and a title.
struct Canvas {
  cv::Mat image{480, 640, CV_8UC3, cv::Scalar(255, 255, 255)};
  cv::Rect area{70, 40, 540, 370};
  void frame(const std::string& title, const std::string& x_label, const std::string& y_label) {
    cv::rectangle(image, area, cv::Scalar(0, 0, 0), 1);
    cv::putText(image, title, {area.x + 90, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {0, 0, 0}, 1,
                cv::LINE_AA);
    cv::putText(image, x_label, {area.x + area.width / 2 - 60, 465}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
                {0, 0, 0}, 1, cv::LINE_AA);
    cv::putText(image, y_label, {5, area.y - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1,
                cv::LINE_AA);
  }
  void tick_x(double fraction, const std::string& text) {
    const int x = area.x + static_cast<int>(fraction * area.width);
    cv::line(image, {x, area.br().y}, {x, area.br().y + 5}, {0, 0, 0});
    cv::putText(image, text, {x - 12, area.br().y + 20}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {0, 0, 0},
                1, cv::LINE_AA);
  }
  void tick_y(double fraction, const std::string& text) {
    const int y = area.br().y - static_cast<int>(fraction * area.height);
    cv::line(image, {area.x - 5, y}, {area.x, y}, {0, 0, 0});
    cv::line(image, {area.x, y}, {area.br().x, y}, {230, 230, 230});
    cv::putText(image, text, {5, y + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {0, 0, 0}, 1, cv::LINE_AA);
  }
  cv::Point at(double fx, double fy) const {
    return {area.x + static_cast<int>(fx * area.width),
            area.br().y - static_cast<int>(fy * area.height)};
  }
  void write(const std::string& file) const {
    if (!macsim::images::write_image(file, image)) throw std::runtime_error("cannot write " + file);
  }
};

std::string format(double v, const char* how) {
  char text[32];
  std::snprintf(text, sizeof text, how, v);
  return text;
}

}  // namespace

void plot_learning_curve(const std::vector<std::pair<int, double>>& curve, const std::string& title,
                         const std::string& file) {
  Canvas c;
  c.frame(title, "training trials (log scale)", "held-out accuracy");
  const double lo = std::log10(std::max(1, curve.empty() ? 1 : curve.front().first));
  const double hi =
      std::max(lo + 1, std::log10(std::max(1, curve.empty() ? 10 : curve.back().first)));
  auto fx = [&](int n) { return (std::log10(std::max(n, 1)) - lo) / (hi - lo); };
  for (int i = 0; i <= 5; ++i) c.tick_y(i / 5.0, format(0.5 + i * 0.1, "%.1f"));
  for (const auto& [n, accuracy] : curve) c.tick_x(fx(n), std::to_string(n));
  cv::Point last;
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const cv::Point p =
        c.at(fx(curve[i].first), std::clamp((curve[i].second - 0.5) / 0.5, 0.0, 1.0));
    if (i) cv::line(c.image, last, p, {200, 90, 20}, 2, cv::LINE_AA);
    cv::circle(c.image, p, 4, {200, 90, 20}, cv::FILLED, cv::LINE_AA);
    last = p;
  }
  c.write(file);
}

void plot_scatter(const Dataset& data, const std::string& x_feature, const std::string& y_feature,
                  const std::string& file) {
  auto index = [&](const std::string& n) {
    const auto at = std::find(data.feature_names.begin(), data.feature_names.end(), n);
    if (at == data.feature_names.end()) throw std::runtime_error("no feature '" + n + "' to plot");
    return static_cast<int>(at - data.feature_names.begin());
  };
  const int xi = index(x_feature), yi = index(y_feature);
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (int i = 0; i < data.features.rows; ++i) {
    x0 = std::min<double>(x0, data.features.at<float>(i, xi));
    x1 = std::max<double>(x1, data.features.at<float>(i, xi));
    y0 = std::min<double>(y0, data.features.at<float>(i, yi));
    y1 = std::max<double>(y1, data.features.at<float>(i, yi));
  }
  if (!(x1 > x0)) x1 = x0 + 1;
  if (!(y1 > y0)) y1 = y0 + 1;
  Canvas c;
  c.frame(data.affordance + ": " + y_feature + " against " + x_feature, x_feature, y_feature);
  for (int i = 0; i <= 4; ++i) {
    c.tick_x(i / 4.0, format(x0 + (x1 - x0) * i / 4, "%.3g"));
    c.tick_y(i / 4.0, format(y0 + (y1 - y0) * i / 4, "%.3g"));
  }
  for (int i = 0; i < data.features.rows; ++i) {
    const double fx = (data.features.at<float>(i, xi) - x0) / (x1 - x0);
    const double fy = (data.features.at<float>(i, yi) - y0) / (y1 - y0);
    cv::circle(c.image, c.at(fx, fy), 3, kClassColours[data.labels[i] % 4], cv::FILLED,
               cv::LINE_AA);
  }
  for (std::size_t k = 0; k < data.classes.size(); ++k) {
    const cv::Point p(c.area.br().x - 130, c.area.y + 18 + 18 * static_cast<int>(k));
    cv::circle(c.image, p, 5, kClassColours[k % 4], cv::FILLED, cv::LINE_AA);
    cv::putText(c.image, data.classes[k], p + cv::Point(10, 5), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                {0, 0, 0}, 1, cv::LINE_AA);
  }
  c.write(file);
}

std::string confusion_text(const Dataset& data, const Evaluation& e) {
  std::string text = "  true \\ predicted";
  for (const auto& c : data.classes) text += "  " + c;
  text += "\n";
  for (int r = 0; r < e.confusion.rows; ++r) {
    text += "  " + data.classes[r];
    for (int c = 0; c < e.confusion.cols; ++c)
      text += "  " + std::to_string(e.confusion.at<int>(r, c));
    text += "\n";
  }
  return text;
}

std::string shape_text(const Dataset& data, const Evaluation& e) {
  // Nothing predicted (no trial to train on, or none held out): nothing to break down.
  if (data.shapes.empty() || e.predicted.size() != e.rows.size() || e.rows.empty()) return {};
  std::map<std::string, std::pair<int, int>> by_shape;  // right, held out
  for (std::size_t i = 0; i < e.rows.size(); ++i) {
    const auto row = static_cast<std::size_t>(e.rows[i]);
    auto& [right, tested] = by_shape[data.shapes[row]];
    right += e.predicted[i] == data.labels[row];
    ++tested;
  }
  std::string text = "  held out by shape:";
  for (const auto& [shape, counts] : by_shape) {
    char part[96];
    std::snprintf(part, sizeof part, " %s %d/%d (%.0f %%)", shape.c_str(), counts.first,
                  counts.second, 100.0 * counts.first / counts.second);
    text += part;
  }
  return text + "\n";
}

}  // namespace affordances
