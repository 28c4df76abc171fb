// The conditions and samples of a SIM_STEP request: checked against the world and the robots'
// newest readings (what a controller reading its topics would see), on the simulation thread at
// each check of the request. No DDS here.
#pragma once

#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "macsim/msg/macsim_msgs.h"
#include "macsim/robot/robot_interface.h"
#include "macsim/sim_core/world.h"

namespace macsim {

/// The newest readings of a robot by name (empty: the first robot), or nullptr.
using LatestReadings = std::function<const robot::Readings*(const std::string& robot)>;

/// A step request's end conditions and recorded samples.
class StepConditions {
 public:
  /// The request's conditions and samples checked against `world` and `readings`, or an error
  /// naming the field at fault.
  static std::variant<StepConditions, std::string> compile(
      const macsim_msgs::msg::dds_::SimulationRequest_& request, const World& world,
      const LatestReadings& readings);
  /// Records the samples and tests the conditions; true once a group of conditions holds.
  bool check(const World& world);
  /// The group that ended the request, or -1.
  int ended_by() const { return ended_by_; }
  /// Every sample recorded so far, check after check.
  const std::vector<double>& samples() const { return samples_; }
  /// True when the request has neither conditions nor samples.
  bool empty() const { return until_.empty() && recorded_.empty(); }
  /// Mixes the world's state hash into the step trace (STEP_TRACE_HASH: after every step).
  void trace(const World& world);
  uint64_t step_trace() const { return trace_; }

 private:
  struct Reading {
    int32_t what = 0;
    std::string robot;
    uint32_t object = 0;
  };
  struct Condition {
    Reading reading;
    int32_t test = 0;
    double value = 0, tolerance = 0;
    int32_t group = 0;
    double best = 0, best_at = 0;  // STEP_TEST_STALLED: the best reading and when it came
    bool started = false;
  };
  double read(const Reading& reading, const World& world) const;

  LatestReadings readings_;
  std::vector<Condition> until_;
  std::vector<Reading> recorded_;
  std::vector<double> samples_;
  int ended_by_ = -1;
  uint64_t trace_ = 0;
};

}  // namespace macsim
