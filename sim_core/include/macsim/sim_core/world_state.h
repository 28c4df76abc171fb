// What changes: the complete, serialisable, hashable state of a world (MuJoCo's "data" beside
// the spec), by part: objects' current descriptions, bodies, doors, robots, time, ids, random
// state.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <utility>
#include <string>
#include <vector>

#include "macsim/sim_core/world_spec.h"

namespace macsim {

/// Pose and velocities of one rigid body (world frame, at the centre of mass).
struct BodyState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  bool enabled = true;  ///< false while it sleeps at rest
  /// Still steps it may take before it falls asleep (World decides sleep: World::step).
  int32_t still_steps_left = 50;
};

/// A force and torque added to a body for the next step (add_force, add_torque), not yet used.
struct PendingWrench {
  uint32_t body = 0;  ///< its index in WorldState::bodies
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
};

/// How far a door is open (the seed's DoorGapAmount).
enum class DoorGap { Closed, Half, Open };

/// What a door-switch structure remembers besides its bodies.
struct DoorFlags {
  bool virtual_trigger = false;  ///< pressed by the supervisor, not by a weight
  bool triggered = false;        ///< pressed, by weight or virtually
  DoorGap gap = DoorGap::Closed;
};

/// Everything needed to put a world back exactly, and nothing it can recompute.
struct WorldState {
  uint64_t steps = 0;                                    ///< time = steps * step size
  unsigned long random_seed = 0;                         ///< ODE's dRand state
  uint32_t next_id = 1;                                  ///< the next object id handed out
  std::vector<std::pair<uint32_t, ObjectSpec>> objects;  ///< id and current description, list order
  std::vector<JointSpec> joints;
  std::vector<DoorSpec> doors;
  std::vector<DoorFlags> door_flags;     ///< one per door
  std::vector<BodyState> bodies;         ///< portable objects' then robots' bodies
  std::vector<std::vector<uint8_t>> robots;  ///< each robot's own state (RobotModel::save_state)
  /// The order the bodies were made in, which ODE's solver follows: object ids, and robots as
  /// -1 - their index. A restore makes them in this order again.
  std::vector<int64_t> body_order;
  /// What was added for the next step, for the bodies that have any (ODE clears it each step).
  std::vector<PendingWrench> wrenches;
};

/// A world's complete state, serialised, marked with the world it belongs to.
struct WorldSnapshot {
  uint64_t fingerprint = 0;    ///< World::fingerprint() of its world; another world refuses it
  std::vector<uint8_t> bytes;  ///< serialize(state): native layout, read back by the same build
};

/// The state as bytes (every field of every part).
std::vector<uint8_t> serialize(const WorldState& state);
/// The state back from serialize()'s bytes; throws std::runtime_error on damaged bytes.
WorldState deserialize(const std::vector<uint8_t>& bytes);
/// 64-bit XXH3 of serialize(state), without building the bytes: equal states, equal hashes.
uint64_t state_hash(const WorldState& state);

}  // namespace macsim
