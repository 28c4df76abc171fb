// What must hold of any world after any sequence of requests and steps: the checks the fuzzers
// and the property tests apply after each step.
#pragma once

#include <optional>
#include <string>

#include "macsim/sim_core/world.h"

namespace macsim::test {

/// The first broken invariant, or nothing: every object's pose and velocities finite and its
/// quaternion of unit norm; every portable object's mass positive, equal to density x volume,
/// with a finite, positive-definite inertia; every robot's pose finite; time finite.
std::optional<std::string> invariant_violation(const World& world);
/// Steps the world `steps` times; after a step that breaks an invariant, says which on stderr
/// and aborts (a fuzzer's finding).
void step_keeping_invariants(World& world, int steps);

}  // namespace macsim::test
