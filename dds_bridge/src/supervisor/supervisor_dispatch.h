// One supervisor request run against a world: (request, world, named snapshots) -> reply.
// No DDS here: SupervisorServer calls it on the simulation thread, unit tests call it directly.
#pragma once

#include <cstdint>
#include <string>

#include "macsim/msg/macsim_msgs.h"
#include "macsim/sim_core/command.h"
#include "macsim/sim_core/snapshot_store.h"
#include "macsim/sim_core/world.h"

namespace macsim {

/// True for an operation that may change the world or its snapshots (a session records it);
/// false for one that only reads (get_*, list_*, find_*, door_count, state_hash).
bool changes_world(int32_t code);

/// Runs a recorded supervisor command (its request in the wire form) as the server did,
/// unanswered (a replay); false for a damaged message.
bool replay(const Command& command, World& world, SnapshotStore& snapshots);

/// The name of an operation code (OP_SET_DENSITY: "set_density"); "operation_<code>" if unknown.
std::string operation_name(int32_t code);

/// Runs the request's operation; the reply echoes client and sequence number and carries the
/// result, or an ERR_* code with a message (the world then unchanged).
macsim_msgs::msg::dds_::SupervisorReply_ dispatch(
    const macsim_msgs::msg::dds_::SupervisorRequest_& request, World& world,
    SnapshotStore& snapshots);

}  // namespace macsim
