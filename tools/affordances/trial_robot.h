// One simulator instance and the robot in it, as a trial controller uses them: the supervisor
// (reset, spawn, ground truth for the label), lock-step simulation control, and the robot's own
// topics (cameras, laser, odometry, crane). run() plays one trial and returns its row.
#pragma once

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgs.h"
#include "trial_record.h"
#include "trial_spec.h"

namespace affordances {

/// The object (or ramp) the supervisor spawns for a trial, as its seed drew it.
macsim_msgs::msg::dds_::Object_ trial_object(const TrialSpec& spec);
/// The object a stack trial's crane carries, where it stands beside the robot.
macsim_msgs::msg::dds_::Object_ carried_object(const Carried& carried);

/// How to reach an instance and how it was started.
struct InstanceOptions {
  int domain = -1;
  std::string profile;  ///< DDS profile XML; empty: FASTRTPS_DEFAULT_PROFILES_FILE
  std::string robot = "kurt";
  double camera_rate = 1.25;                 ///< Hz: the instance's --camera-rate
  bool hash_every_step = false;              ///< the trace mixes the state hash of every step
  bool keep_inputs = false;                  ///< TrialRecord::inputs holds what was perceived
  std::chrono::milliseconds timeout{10000};  ///< wall time an answer or a sample may take
};

/// The instance stopped answering (killed, hung, gone from the network).
struct InstanceLost : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A trial controller attached to one lock-step simulator.
class TrialRobot {
 public:
  explicit TrialRobot(const InstanceOptions& options);
  ~TrialRobot();
  TrialRobot(const TrialRobot&) = delete;
  TrialRobot& operator=(const TrialRobot&) = delete;

  /// Waits until the instance's supervisor, simulation control and robot are matched and it
  /// steps on request; throws InstanceLost with what is missing.
  void connect(std::chrono::milliseconds timeout);
  /// Plays one trial from a scoped reset; throws InstanceLost when the instance does not answer.
  TrialRecord run(const TrialSpec& spec);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace affordances
