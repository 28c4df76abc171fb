// MuJoCo (Debian's libmujoco 2.2.2) holding the same scene as sim_core: MJCF generated from the
// WorldSpec (fixed objects as world geoms, portable ones as free bodies, doors' joints with
// velocity servos, the KURT3D of vehicle_layout.h as a body tree). A benchmark peer only.
#pragma once

#include <string>
#include <vector>

#include "peer_engine.h"

struct mjModel_;
struct mjData_;

namespace macsim::bench {

/// How the MJCF is written: MuJoCo's defaults unless a scene needs otherwise.
struct MujocoOptions {
  /// "Euler" (MuJoCo's default) or "implicit" (velocity servos with stiff gains stay stable).
  std::string integrator = "Euler";
  /// Several contacts between convex shapes (stacked cylinders stand), MuJoCo's multiccd flag.
  bool multiccd = false;
};

/// The MuJoCo library's version, e.g. "2.2.2".
std::string mujoco_version();

/// The MJCF text of a WorldSpec (exposed for the README and for inspection).
std::string mjcf_from_spec(const WorldSpec& spec, const MujocoOptions& options = {});

/// A MuJoCo model and data built from a WorldSpec.
class MujocoWorld : public PeerEngine {
 public:
  /// Throws std::runtime_error with MuJoCo's message when the model does not compile.
  explicit MujocoWorld(const WorldSpec& spec, const MujocoOptions& options = {});
  ~MujocoWorld() override;
  MujocoWorld(const MujocoWorld&) = delete;
  MujocoWorld& operator=(const MujocoWorld&) = delete;

  void step() override;
  void drive(double speed) override;
  std::vector<Eigen::Vector3d> object_positions() const override;
  Pose robot_pose() const override;
  double kinetic_energy() const override;
  int overflows() const override;

 private:
  mjModel_* model_ = nullptr;
  mjData_* data_ = nullptr;
  std::vector<int> portable_;  ///< body ids in spec order
  std::vector<int> wheel_actuators_;
  int chassis_ = -1;
  double wheel_radius_ = 0.06;
};

}  // namespace macsim::bench
