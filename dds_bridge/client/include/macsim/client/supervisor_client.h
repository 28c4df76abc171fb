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
  /// A request with just a command.
  static Request request(int32_t command);
};

}  // namespace macsim::client
