// Layouts by seed: a world's <VARIATION> places its chosen objects and its robots at random
// within the documented areas; the same seed gives the same layout.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "macsim/sim_core/world_spec.h"

namespace macsim {

/// Places the objects and robots `spec.variation` names; throws WorldFileError (naming the
/// <VARIATION> element) if the world has none, names more than 1000 objects, or the objects do
/// not fit with their clearance.
/// Returns one line per thing moved ("name at x, y"), for the log.
std::vector<std::string> vary_world(WorldSpec& spec, uint32_t seed);

}  // namespace macsim
