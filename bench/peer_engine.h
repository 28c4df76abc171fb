// One physics engine stepping one scene, as bench_peers compares them: sim_core, raw ODE and
// MuJoCo each implement this, built from the same WorldSpec.
#pragma once

#include <string>
#include <vector>

#include "macsim/sim_core/world_spec.h"

namespace macsim::bench {

/// An engine holding one scene; read-outs are in the world frame, SI units.
class PeerEngine {
 public:
  virtual ~PeerEngine() = default;
  /// Advances one fixed step (the spec's physics step).
  virtual void step() = 0;
  /// Drives the robot (if any) straight ahead at `speed` m/s rim speed on every wheel.
  virtual void drive(double speed) = 0;
  /// Origins of the portable objects' frames (where the spec places them), in spec order.
  virtual std::vector<Eigen::Vector3d> object_positions() const = 0;
  /// The robot's chassis pose (its frame differs by engine: compare x, y and heading only).
  virtual Pose robot_pose() const = 0;
  /// Translational kinetic energy of the portable objects (robot excluded), J.
  virtual double kinetic_energy() const = 0;
  /// Steps in which the engine dropped contacts or constraints for lack of room (0: none).
  virtual int overflows() const { return 0; }
};

}  // namespace macsim::bench
