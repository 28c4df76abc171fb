// Whether two recorded sessions are the same run (macsim --compare A B): every command, request,
// state hash and file alike, the clients' random identities and DDS writers taken as the same
// when they first appear in the same order, and the world file's path as recorded aside.
#pragma once

#include <optional>
#include <string>

#include "macsim/sim_core/session.h"

namespace macsim {

/// Where two sessions part: the first record (by step) that differs, both sides said; nullopt
/// when they are the same run.
std::optional<std::string> first_difference(const Session& a, const Session& b);

}  // namespace macsim
