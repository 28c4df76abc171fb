// One supervisor request run against a world: (request, world, named snapshots) -> reply.
// No DDS here: SupervisorServer calls it on the simulation thread, unit tests call it directly.
#pragma once

#include <cstdint>
#include <string>

#include "macsim/msg/macsim_msgs.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/sim_core/command.h"
#include "macsim/sim_core/snapshot_store.h"
#include "macsim/sim_core/world.h"
#include "typed_request.h"

namespace macsim {

/// True for an operation that may change the world or its snapshots (a session records it);
/// false for one that only reads (get_*, list_*, find_*, door_count, state_hash).
bool changes_world(int32_t code);

/// A supervisor request as the runner queues it.
using SupervisorCall = TypedRequest<macsim_msgs::msg::dds_::SupervisorRequest_PubSubType>;

/// The request as a command (named by its operation); a reset or a snapshot restored carries
/// the robot commands its client sent before it.
Command supervisor_command(const macsim_msgs::msg::dds_::SupervisorRequest_& request);

/// The name of an operation code (OP_SET_DENSITY: "set_density"); "operation_<code>" if unknown.
std::string operation_name(int32_t code);

/// Runs the request's operation; the reply echoes client and sequence number and carries the
/// result, or an ERR_* code with a message (the world then unchanged).
macsim_msgs::msg::dds_::SupervisorReply_ dispatch(
    const macsim_msgs::msg::dds_::SupervisorRequest_& request, World& world,
    SnapshotStore& snapshots);

}  // namespace macsim
