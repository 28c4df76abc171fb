#include "trial_record.h"

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

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

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

}  // namespace

std::string csv_header(Affordance a) {
  std::string h = "affordance,generator,seed,label";
  for (const auto& f : feature_names(a)) h += "," + f;
  h += ",seen,laser_hit,shape,size_x,size_y,size_z,material,density,mass,friction,magnetizable,"
       "colour_r,colour_g,colour_b,x,y,ramp_width,ramp_height,ramp_angle";
  if (a == Affordance::Stack)
    h += ",carried_shape,carried_size_x,carried_size_y,carried_size_z,carried_mass";
  if (a == Affordance::Traverse) h += ",yaw,fixed,gap";
  h += ",raised,moved,rolled,rise,progress";
  if (a == Affordance::Stack) h += ",offset,settle,a_tilt,b_tilt";
  if (a == Affordance::Traverse) h += ",passed";
  h += ",sim_time,steps,final_hash,trace,instance,wall_time";
  return h;
}

std::string csv_row(const TrialRecord& t) {
  const TrialSpec& s = t.spec;
  const Affordance a = s.affordance;
  std::string row = std::string(name(a)) + "," + name(s.generator) + "," + std::to_string(s.seed) +
                    "," + t.outcome.label;
  for (double f : features(t.percept, a)) row += "," + number(f);
  row += std::string(",") + (t.percept.seen ? "1" : "0") + "," + (t.percept.laser_hit ? "1" : "0");
  row += std::string(",") + name(s.shape);
  for (double v : s.size) row += "," + number(v);
  row += "," + s.material + "," + number(s.density) + "," + number(s.mass) + "," +
         number(s.friction) + "," + (s.magnetizable ? "1" : "0");
  for (float c : s.colour) row += "," + number(c);
  for (double v : {s.x, s.y, s.ramp_width, s.ramp_height, s.ramp_angle}) row += "," + number(v);
  if (a == Affordance::Stack) {
    row += std::string(",") + name(s.carried.shape);
    for (double v : s.carried.size) row += "," + number(v);
    row += "," + number(s.carried.mass);
  }
  if (a == Affordance::Traverse)
    row += "," + number(s.yaw) + "," + (s.fixed ? "1" : "0") + "," + number(s.gap);
  const Outcome& o = t.outcome;
  for (double v : {o.raised, o.moved, o.rolled, o.rise, o.progress}) row += "," + number(v);
  if (a == Affordance::Stack)
    for (double v : {o.offset, o.settle, o.a_tilt, o.b_tilt}) row += "," + number(v);
  if (a == Affordance::Traverse) row += "," + number(o.passed);
  row += "," + number(t.sim_time) + "," + std::to_string(t.steps) + "," + hex(t.final_hash) + "," +
         hex(t.trace) + "," + std::to_string(t.instance) + "," + number(t.wall_time);
  return row;
}

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
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  CsvTable table;
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path + ": empty (no header line)");
  table.columns = split(line);
  int number_of_line = 1;
  std::vector<std::pair<int, std::string>> lines;
  while (std::getline(in, line)) {
    ++number_of_line;
    if (line.empty()) continue;
    lines.emplace_back(number_of_line, line);
  }
  const bool ended_cleanly = [&] {
    std::ifstream again(path, std::ios::binary | std::ios::ate);
    if (again.tellg() <= 0) return true;
    again.seekg(-1, std::ios::end);
    return again.get() == '\n';
  }();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    auto fields = split(lines[i].second);
    if (fields.size() != table.columns.size()) {
      if (i + 1 == lines.size() && !ended_cleanly) break;  // a row cut short by a kill
      throw std::runtime_error(path + ":" + std::to_string(lines[i].first) + ": " +
                               std::to_string(fields.size()) + " fields, the header has " +
                               std::to_string(table.columns.size()));
    }
    table.rows.push_back(std::move(fields));
  }
  return table;
}

std::string trial_key(const std::string& affordance, const std::string& generator, uint64_t seed) {
  return affordance + "," + generator + "," + std::to_string(seed);
}

}  // namespace affordances
