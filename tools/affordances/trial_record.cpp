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

std::string csv_header() {
  std::string h = "affordance,generator,seed,label";
  for (const char* f : feature_names()) h += std::string(",") + f;
  h += ",seen,laser_hit,shape,size_x,size_y,size_z,material,density,mass,friction,magnetizable,"
       "colour_r,colour_g,colour_b,x,y,ramp_width,ramp_height,ramp_angle,"
       "raised,moved,rolled,rise,progress,sim_time,steps,final_hash,trace,instance,wall_time";
  return h;
}

std::string csv_row(const TrialRecord& t) {
  const TrialSpec& s = t.spec;
  std::string row = std::string(name(s.affordance)) + "," + name(s.generator) + "," +
                    std::to_string(s.seed) + "," + t.outcome.label;
  for (double f : features(t.percept)) row += "," + number(f);
  row += std::string(",") + (t.percept.seen ? "1" : "0") + "," + (t.percept.laser_hit ? "1" : "0");
  row += std::string(",") + name(s.shape);
  for (double v : s.size) row += "," + number(v);
  row += "," + s.material + "," + number(s.density) + "," + number(s.mass) + "," +
         number(s.friction) + "," + (s.magnetizable ? "1" : "0");
  for (float c : s.colour) row += "," + number(c);
  for (double v :
       {s.x, s.y, s.ramp_width, s.ramp_height, s.ramp_angle, t.outcome.raised, t.outcome.moved,
        t.outcome.rolled, t.outcome.rise, t.outcome.progress, t.sim_time})
    row += "," + number(v);
  row += "," + std::to_string(t.steps) + "," + hex(t.final_hash) + "," + hex(t.trace) + "," +
         std::to_string(t.instance) + "," + number(t.wall_time);
  return row;
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
