// What a replay makes of the servers' requests a session recorded: their typed values again, as
// the servers had queued them (sim_core reads a session's records as names and bytes only).
#pragma once

#include <memory>

#include "macsim/sim_core/command.h"

namespace macsim {

/// The typed request of a server's request a session recorded (replay_session()'s
/// RequestReader): a supervisor request or a simulation_interfaces service's; nullptr for bytes
/// that are not one.
std::shared_ptr<const Request> read_recorded_request(const Command& recorded);

}  // namespace macsim
