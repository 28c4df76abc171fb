// What changes: the complete, restorable state of a world (MuJoCo's "data" beside the spec).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <utility>
#include <vector>

#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world_spec.h"

namespace macsim {

/// Pose and velocities of one rigid body (world frame, at the centre of mass).
struct BodyState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  bool enabled = true;  ///< false while ODE lets it sleep at rest
};

/// Everything needed to put a world back exactly: its current description (objects may have
/// been created, destroyed or changed) and its dynamics, time and random state.
struct WorldSnapshot {
  uint64_t steps = 0;
  unsigned long random_seed = 0;                          ///< ODE's dRand state
  uint32_t next_id = 1;
  std::vector<std::pair<uint32_t, ObjectSpec>> objects;   ///< id and description, list order
  std::vector<JointSpec> joints;
  std::vector<DoorSpec> doors;
  std::vector<uint8_t> door_flags;                        ///< virtual trigger, triggered, gap
  std::vector<BodyState> bodies;                          ///< objects' then robots' bodies
  std::vector<KurtRobot::ControllerState> robots;
};

}  // namespace macsim
