// Simulation control over DDS: pause, run, real-time factor, lock-step, load world, features.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/sim_core/simulation.h"

namespace macsim {

/// How the step loop runs; changed only on the simulation thread (by queued requests).
struct LoopControl {
  bool paused = false;
  double real_time_factor = 1.0;  ///< 0: as fast as possible
  uint64_t pending_steps = 0;     ///< lock-step: steps still to do for the waiting request
};

/// Serves SimulationRequests. The loop asks should_step() before and calls after_publish()
/// after each step; a SIM_STEP request is answered once its last step's data is out.
class SimulationServer {
 public:
  SimulationServer(dds::Participant& participant, Simulation& simulation, LoopControl initial);
  ~SimulationServer();

  /// True if the loop should step now (running, or lock-step steps pending).
  bool should_step() const { return control_.pending_steps > 0 || !control_.paused; }
  /// After a step and its publishing: counts lock-step steps down and replies when done.
  void after_publish();
  const LoopControl& control() const { return control_; }

 private:
  using Request = macsim_msgs::msg::dds_::SimulationRequest_;
  using Reply = macsim_msgs::msg::dds_::SimulationReply_;

  void execute(const Request& request);
  Reply reply_to(const Request& request, int code, const std::string& message) const;
  void send(const Reply& reply);

  Simulation& simulation_;
  LoopControl control_;
  std::optional<Request> stepping_;  // the SIM_STEP request being served
  std::map<std::string, Reply> last_reply_;  // by client
  dds::Writer<macsim_msgs::msg::dds_::SimulationReply_PubSubType> replies_;
  std::unique_ptr<dds::Reader<macsim_msgs::msg::dds_::SimulationRequest_PubSubType>> requests_;
};

}  // namespace macsim
