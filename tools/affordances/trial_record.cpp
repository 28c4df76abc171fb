#include "trial_record.h"

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "csv_writer.h"

namespace affordances {

namespace {

std::string number(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

std::string hex(uint64_t v) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "%016" PRIx64, v);
  return buffer;
}

std::string flag(bool v) { return v ? "1" : "0"; }

/// What a row is written from: the record and its perceived features (computed once a row).
struct RowSource {
  const TrialRecord& t;
  std::vector<double> features;
};
using Columns = csv::Columns<RowSource>;

/// A column of a number the record holds at `get`.
template <class Get>
Columns::Field numeric(Get get) {
  return [get](const RowSource& r) { return number(get(r.t)); };
}

/// The columns of an affordance's rows: lift, push and climb share theirs; stack and traverse
/// add their features, what they put down and what they measure. Instance and wall time last.
Columns make_columns(Affordance a) {
  Columns c;
  c.add("affordance", [](const RowSource& r) { return std::string(name(r.t.spec.affordance)); })
      .add("generator", [](const RowSource& r) { return std::string(name(r.t.spec.generator)); })
      .add("seed", [](const RowSource& r) { return std::to_string(r.t.spec.seed); })
      .add("label", [](const RowSource& r) { return r.t.outcome.label; });
  const auto& names = feature_names(a);
  for (std::size_t i = 0; i < names.size(); ++i)
    c.add(names[i], [i](const RowSource& r) { return number(r.features.at(i)); });
  c.add("seen", [](const RowSource& r) { return flag(r.t.percept.seen); })
      .add("laser_hit", [](const RowSource& r) { return flag(r.t.percept.laser_hit); })
      .add("shape", [](const RowSource& r) { return std::string(name(r.t.spec.shape)); });
  for (std::size_t i = 0; i < 3; ++i)
    c.add(std::string("size_") + "xyz"[i], numeric([i](const TrialRecord& t) { return t.spec.size[i]; }));
  c.add("material", [](const RowSource& r) { return r.t.spec.material; })
      .add("density", numeric([](const TrialRecord& t) { return t.spec.density; }))
      .add("mass", numeric([](const TrialRecord& t) { return t.spec.mass; }))
      .add("friction", numeric([](const TrialRecord& t) { return t.spec.friction; }))
      .add("magnetizable", [](const RowSource& r) { return flag(r.t.spec.magnetizable); });
  for (std::size_t i = 0; i < 3; ++i)
    c.add(std::string("colour_") + "rgb"[i],
          numeric([i](const TrialRecord& t) { return t.spec.colour[i]; }));
  c.add("x", numeric([](const TrialRecord& t) { return t.spec.x; }))
      .add("y", numeric([](const TrialRecord& t) { return t.spec.y; }))
      .add("ramp_width", numeric([](const TrialRecord& t) { return t.spec.ramp_width; }))
      .add("ramp_height", numeric([](const TrialRecord& t) { return t.spec.ramp_height; }))
      .add("ramp_angle", numeric([](const TrialRecord& t) { return t.spec.ramp_angle; }));
  if (a == Affordance::Stack) {
    c.add("carried_shape",
          [](const RowSource& r) { return std::string(name(r.t.spec.carried.shape)); });
    for (std::size_t i = 0; i < 3; ++i)
      c.add(std::string("carried_size_") + "xyz"[i],
            numeric([i](const TrialRecord& t) { return t.spec.carried.size[i]; }));
    c.add("carried_mass", numeric([](const TrialRecord& t) { return t.spec.carried.mass; }));
  }
  if (a == Affordance::Traverse) {
    c.add("yaw", numeric([](const TrialRecord& t) { return t.spec.yaw; }))
        .add("fixed", [](const RowSource& r) { return flag(r.t.spec.fixed); })
        .add("gap", numeric([](const TrialRecord& t) { return t.spec.gap; }));
  }
  c.add("raised", numeric([](const TrialRecord& t) { return t.outcome.raised; }))
      .add("moved", numeric([](const TrialRecord& t) { return t.outcome.moved; }))
      .add("rolled", numeric([](const TrialRecord& t) { return t.outcome.rolled; }))
      .add("rise", numeric([](const TrialRecord& t) { return t.outcome.rise; }))
      .add("progress", numeric([](const TrialRecord& t) { return t.outcome.progress; }));
  if (a == Affordance::Stack) {
    c.add("offset", numeric([](const TrialRecord& t) { return t.outcome.offset; }))
        .add("settle", numeric([](const TrialRecord& t) { return t.outcome.settle; }))
        .add("a_tilt", numeric([](const TrialRecord& t) { return t.outcome.a_tilt; }))
        .add("b_tilt", numeric([](const TrialRecord& t) { return t.outcome.b_tilt; }));
  }
  if (a == Affordance::Traverse)
    c.add("passed", numeric([](const TrialRecord& t) { return t.outcome.passed; }));
  c.add("sim_time", numeric([](const TrialRecord& t) { return t.sim_time; }))
      .add("steps", [](const RowSource& r) { return std::to_string(r.t.steps); })
      .add("final_hash", [](const RowSource& r) { return hex(r.t.final_hash); })
      .add("trace", [](const RowSource& r) { return hex(r.t.trace); })
      .add("instance", [](const RowSource& r) { return std::to_string(r.t.instance); })
      .add("wall_time", numeric([](const TrialRecord& t) { return t.wall_time; }));
  return c;
}

const Columns& columns(Affordance a) {
  static const std::map<Affordance, Columns> kColumns = [] {
    std::map<Affordance, Columns> all;
    for (auto each : {Affordance::Lift, Affordance::Push, Affordance::Climb, Affordance::Stack,
                      Affordance::Traverse})
      all.emplace(each, make_columns(each));
    return all;
  }();
  return kColumns.at(a);
}

}  // namespace

std::string csv_header(Affordance a) { return columns(a).header(); }

std::vector<std::string> csv_fields(const TrialRecord& t) {
  const Affordance a = t.spec.affordance;
  return columns(a).fields(RowSource{t, features(t.percept, a)});
}

std::string csv_row(const TrialRecord& t) { return csv::join(csv_fields(t)); }

const std::vector<std::string>& labels(Affordance a) {
  static const std::map<Affordance, std::vector<std::string>> kLabels{
      {Affordance::Lift, {"liftable", "not_liftable"}},
      {Affordance::Push, {"pushed", "rolled", "stalled"}},
      {Affordance::Climb, {"climbed", "slid_back", "stalled"}},
      {Affordance::Stack, {"stacked", "slid_off", "toppled"}},
      {Affordance::Traverse, {"traversable", "not_traversable"}}};
  return kLabels.at(a);
}

std::optional<std::size_t> CsvTable::column(const std::string& n) const {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == n) return i;
  }
  return std::nullopt;
}

CsvTable read_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  auto records = csv::parse(text.str());
  if (records.empty()) throw std::runtime_error(path + ": empty (no header line)");
  CsvTable table;
  table.columns = std::move(records.front().fields);
  for (std::size_t i = 1; i < records.size(); ++i) {
    auto& record = records[i];
    if (record.fields.size() != table.columns.size()) {
      if (i + 1 == records.size() && !record.ended) break;  // a row cut short by a kill
      throw std::runtime_error(path + ":" + std::to_string(record.line) + ": " +
                               std::to_string(record.fields.size()) + " fields, the header has " +
                               std::to_string(table.columns.size()));
    }
    table.rows.push_back(std::move(record.fields));
  }
  return table;
}

std::string trial_key(const std::string& affordance, const std::string& generator, uint64_t seed) {
  return csv::join({affordance, generator, std::to_string(seed)});
}

}  // namespace affordances
