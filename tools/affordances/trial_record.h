// One trial's result as a CSV row: what it was (the spec), what the robot perceived, what
// happened (the label from the world state) and what it cost. Rows are read back to resume a
// run and to learn. Header and rows come from one list of columns (csv_writer.h), quoted as
// RFC 4180 has it.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "macsim/affordances/perception.h"
#include "trial_spec.h"

namespace affordances {

// The one perception (the SDK's: controllers compute the same features from the same code).
using macsim::affordances::feature_names;
using macsim::affordances::features;
using macsim::affordances::GroundGrid;
using macsim::affordances::Percept;
using macsim::affordances::perceive_cloud;
using macsim::affordances::perceive_image;
using macsim::affordances::perceive_scan;
using macsim::affordances::SensorMount;

/// What happened, measured on the world state (ground truth), and the label it gives.
struct Outcome {
  std::string label;    ///< lift: liftable | not_liftable; push: pushed | rolled | stalled;
                        ///< climb: climbed | slid_back | stalled; stack: stacked | slid_off |
                        ///< toppled; traverse: traversable | not_traversable
  double raised = 0;    ///< lift: m the object came up (the lower of after raising and 1 s on)
  double moved = 0;     ///< push: m the object moved on the floor; stack: m the base moved
  double rolled = 0;    ///< push: rad it turned about horizontal axes
  double rise = 0;      ///< climb: m the robot rose at most
  double progress = 0;  ///< climb, traverse: m the robot got ahead at most
  double offset = 0;    ///< stack: m from the base's top middle to the carried object's, level
  double settle = 0;    ///< stack: m from the base's top up to the carried object's bottom
  double a_tilt = 0;    ///< stack: rad the carried object leans (its axis from upright)
  double b_tilt = 0;    ///< stack: rad the base leans (a lying cylinder: its axis from level)
  double passed = 0;    ///< traverse: m the robot's middle got past the far edge (< 0: short)
};

struct TrialRecord {
  TrialSpec spec;
  Percept percept;
  macsim::affordances::SensorInputs inputs;  ///< what it was perceived from (keep_inputs only)
  Outcome outcome;
  double sim_time = 0;      ///< s of sim time the trial took
  uint64_t steps = 0;       ///< physics steps
  uint64_t final_hash = 0;  ///< the simulator's state hash at the end
  uint64_t trace = 0;       ///< a hash of the state hashes after every step request
  int instance = 0;         ///< which simulator ran it (not part of the result)
  double wall_time = 0;     ///< s it took (not part of the result)
};

/// The CSV header line of an affordance's rows (no newline): lift, push and climb share one;
/// stack and traverse add their features, what they put down and what they measure.
std::string csv_header(Affordance affordance = Affordance::Lift);
/// A row (no newline), of the columns of csv_header(record.spec.affordance). Columns instance
/// and wall_time come last; every other column is the same for the same trial wherever and
/// whenever it runs.
std::string csv_row(const TrialRecord& record);
/// The row's fields, unquoted.
std::vector<std::string> csv_fields(const TrialRecord& record);
/// The labels an affordance's trials can have.
const std::vector<std::string>& labels(Affordance affordance);

/// A CSV file read back: the header's names and the rows' fields by column.
struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  /// Index of a column, or nullopt.
  std::optional<std::size_t> column(const std::string& name) const;
};
/// Reads a CSV of trial rows (quoted fields too); throws std::runtime_error naming the file and
/// line of a row whose field count does not match the header. A last row cut short (a killed
/// run) is dropped.
CsvTable read_csv(const std::string& path);

/// The key of a trial in a file: its first three columns (affordance, generator, seed) as a
/// row writes them.
std::string trial_key(const std::string& affordance, const std::string& generator, uint64_t seed);

}  // namespace affordances
