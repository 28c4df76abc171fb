// Internal records of World, shared by its implementation files.
#pragma once

#include <ode/ode.h>

#include "macsim/sim_core/world.h"
#include "ode_support.h"

namespace macsim {

namespace detail {

/// An object as ODE holds it, beside its current description.
struct ObjectRecord {
  ObjectId id = 0;
  ObjectSpec spec;  // pose: where it was placed (for jointed bodies: the joint's zero)
  dBodyID body = nullptr;
  std::vector<dGeomID> geoms;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();  // centre of mass in the object's frame
  detail::GeomTag tag;
  int door = -1;  // index of the door it belongs to, -1 if none
};

/// A joint and, while it is being rebuilt, the position it had.
struct JointRecord {
  JointSpec spec;
  dJointID joint = nullptr;
  double position = 0.0;  // slider m / hinge rad, kept across a rebuild
};

/// A door-switch structure and its runtime state.
struct DoorRecord {
  DoorSpec spec;
  JointRecord* door_joint = nullptr;
  JointRecord* switch_joint = nullptr;
  DoorFlags flags;
};

/// InvalidArgument with that message.
inline Status invalid_argument(const std::string& message) {
  return Status::error(ErrorCode::InvalidArgument, message);
}

/// Pose of a body's centre of mass and its velocities.
BodyState body_state(dBodyID body);
void set_body_state(dBodyID body, const BodyState& state);
/// True if every number of the state is finite and the speeds are physically plausible.
bool plausible(const BodyState& state);
/// How deep a point lies inside a geom (negative: outside). ODE's colliders miss some deep,
/// concentric overlaps (a box centred in a cylinder gives no contact); this catches them.
double point_depth(dGeomID g, const dReal* p);
}  // namespace detail

}  // namespace macsim
