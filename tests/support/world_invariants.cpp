#include "support/world_invariants.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "macsim/sim_core/kurt_robot.h"

namespace macsim::test {

std::optional<std::string> invariant_violation(const World& world) {
  if (!std::isfinite(world.time())) return "the time is not finite";
  for (const ObjectId id : world.objects().object_ids()) {
    const ObjectSpec* spec = world.objects().object(id);
    if (!spec) return "object " + std::to_string(id) + " is listed but has no description";
    const std::string name = "'" + spec->name + "': ";
    const auto state = world.objects().object_state(id);
    if (!state.ok()) return name + "no state: " + state.status.message;
    const ObjectState& s = state.value;
    if (!s.pose.position.allFinite() || !s.linear_velocity.allFinite() ||
        !s.angular_velocity.allFinite()) {
      return name + "a pose or velocity is not finite";
    }
    if (!(std::abs(s.pose.orientation.norm() - 1.0) < 1e-6)) {
      return name + "the orientation is not a unit quaternion";
    }
    if (!spec->portable) continue;
    const auto mass = world.objects().object_mass(id);
    if (!mass.ok() || !(mass.value > 0) || !std::isfinite(mass.value)) {
      return name + "the mass is not positive and finite";
    }
    if (!(spec->density > 0) || !(std::abs(mass.value - spec->mass()) <= 1e-9 * mass.value)) {
      return name + "the mass " + std::to_string(mass.value) + " kg is not density x volume (" +
             std::to_string(spec->mass()) + " kg)";
    }
    const auto inertia = world.objects().object_inertia(id);
    if (!inertia.ok() || !inertia.value.allFinite() ||
        !(inertia.value.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff() > 0)) {
      return name + "the inertia is not finite and positive definite";
    }
  }
  for (const auto& robot : world.robots()) {
    const Pose pose = robot->base_link_pose();
    if (!pose.position.allFinite() || !pose.orientation.coeffs().allFinite()) {
      return "robot '" + robot->name() + "': the pose is not finite";
    }
  }
  return std::nullopt;
}

void step_keeping_invariants(World& world, int steps) {
  for (int i = 0; i < steps; ++i) {
    world.step();
    if (auto broken = invariant_violation(world)) {
      std::fprintf(stderr, "invariant broken after step %d: %s\n", i + 1, broken->c_str());
      std::abort();
    }
  }
}

}  // namespace macsim::test
