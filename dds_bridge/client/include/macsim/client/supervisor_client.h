// Handles on the simulator's supervisor and on its simulation control, over DDS.
#pragma once

#include "macsim/client/request_reply.h"
#include "macsim/client/supervisor_requests.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"

namespace macsim::client {

/// Calls supervisor operations (macsim_msgs OP_*): create, destroy, move, resize, ... objects;
/// the requests come from supervisor_requests.h, e.g. call(supervisor::set_mass(id, 0.2)).
class SupervisorClient : public RequestReply<macsim_msgs::msg::dds_::SupervisorRequest_PubSubType,
                                             macsim_msgs::msg::dds_::SupervisorReply_PubSubType> {
 public:
  /// `client_id` empty: one is made from the process id.
  explicit SupervisorClient(dds::Participant& participant, std::string client_id = "")
      : RequestReply(participant, dds::topics::kSupervisorRequest, dds::topics::kSupervisorReply,
                     std::move(client_id)) {}
};

/// Controls the simulation (macsim_msgs SIM_*): pause, run, real-time factor, lock-step steps,
/// load a world, ask what the participant supports.
class SimulationClient : public RequestReply<macsim_msgs::msg::dds_::SimulationRequest_PubSubType,
                                             macsim_msgs::msg::dds_::SimulationReply_PubSubType> {
 public:
  explicit SimulationClient(dds::Participant& participant, std::string client_id = "")
      : RequestReply(participant, dds::topics::kSimulationRequest, dds::topics::kSimulationReply,
                     std::move(client_id)) {}

  /// Lock-step: advances `steps` steps; the reply carries the new sim time and state hash.
  std::optional<Reply> step(uint64_t steps = 1,
                            std::chrono::milliseconds timeout = std::chrono::seconds(10));
  /// Ends this client's step request `sequence_number` (0: whichever runs), e.g. one a timeout
  /// left running or one another thread waits on; the reply carries its steps done and asked
  /// (ERR_NOT_APPLICABLE if none runs).
  std::optional<Reply> cancel(uint64_t sequence_number = 0,
                              std::chrono::milliseconds timeout = std::chrono::seconds(10));
  /// A request with just a command.
  static Request request(int32_t command);
};

/// Parts of a SIM_STEP request that ends on a condition (macsim_msgs STEP_*): e.g. steps until
/// the odometry passes 0.3 m, checked every tick, recording the crane's hoist at every check.
namespace step_until {
using Condition = macsim_msgs::msg::dds_::StepCondition_;
/// A SIM_STEP request of at most `steps` steps, conditions checked every `check_every`.
SimulationClient::Request request(uint64_t steps, uint32_t check_every, uint32_t options = 0);
/// The robot's (or, for STEP_READ_OBJECT_*, the object's) reading, to record as a sample.
Condition reading(int32_t what, uint32_t object_id = 0);
/// reading > value.
Condition above(int32_t what, double value, int32_t group = 0, uint32_t object_id = 0);
/// reading < value.
Condition below(int32_t what, double value, int32_t group = 0, uint32_t object_id = 0);
/// |reading - value| < tolerance.
Condition near(int32_t what, double value, double tolerance, int32_t group = 0);
/// The reading has not risen `rise` above its best for `seconds`.
Condition stalled(int32_t what, double seconds, double rise, int32_t group = 0);
}  // namespace step_until

}  // namespace macsim::client
