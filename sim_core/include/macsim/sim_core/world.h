// What ODE holds: a world built from a WorldSpec, stepped at a fixed step.
#pragma once

#include <ode/common.h>

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world_spec.h"

namespace macsim {

namespace detail {
struct GeomTag;
}

/// A body or fixed geometry built from an ObjectSpec.
struct WorldObject {
  ObjectSpec spec;
  dBodyID body = nullptr;  ///< null for fixed objects
  dGeomID geom = nullptr;
};

/// The ODE world of one simulation: bodies, geoms, joints, robots, contacts, sim time.
class World {
 public:
  /// Builds the world; throws WorldFileError (with the spec's file and line) on what cannot be
  /// built, such as an unknown robot type. Seeds ODE's random generator for determinism.
  explicit World(WorldSpec spec);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Advances one fixed step: robots' motors, collisions, QuickStep, encoders.
  void step();

  double time() const { return static_cast<double>(steps_) * spec_.physics.step; }
  uint64_t steps() const { return steps_; }
  double step_size() const { return spec_.physics.step; }
  const WorldSpec& spec() const { return spec_; }

  /// The robot of that name, or nullptr.
  KurtRobot* robot(const std::string& name);
  const std::vector<std::unique_ptr<KurtRobot>>& robots() const { return robots_; }
  const std::vector<WorldObject>& objects() const { return objects_; }
  /// Ground truth pose of an object (fixed objects report their geometry's pose).
  Pose object_pose(const WorldObject& object) const;
  /// Contact points created in the last step.
  int contact_count() const { return contacts_; }

 private:
  static void near_callback(void* data, dGeomID a, dGeomID b);
  void add_object(const ObjectSpec& spec, int owner);

  WorldSpec spec_;
  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contact_group_ = nullptr;
  void* threading_ = nullptr;
  dGeomID ground_ = nullptr;
  std::deque<detail::GeomTag> tags_;  // stable addresses for geom user data
  std::vector<WorldObject> objects_;
  std::vector<std::unique_ptr<KurtRobot>> robots_;
  uint64_t steps_ = 0;
  int contacts_ = 0;
};

}  // namespace macsim
