// Internal helpers between Eigen and ODE, and the tag every geom carries for contacts.
#pragma once

#include <ode/ode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "macsim/sim_core/world_spec.h"

namespace macsim::detail {

/// Stored in every geom's user data: who owns it (no self-contacts) and its friction.
struct GeomTag {
  int group = -1;                      ///< collision group; geoms of one group never collide
  double friction = 1.0;               ///< Coulomb mu; a contact uses the geometric mean of both
  double bounce = 0.0;                 ///< restitution; a contact uses the larger
  double bounce_velocity = 0.1;        ///< m/s below which nothing bounces
  const ObjectSpec* object = nullptr;  ///< the object it belongs to (magnetizable, name)
};

/// An argument check of ODE that failed (its debug or error handler): thrown instead of ODE's
/// abort. ODE checks at an API entry before it changes anything, so the world stays as it was;
/// thrown inside a collision or a step, the world it came from cannot be trusted any more.
class OdeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Process-wide ODE set-up (dInitODE2, handlers that throw OdeError) and per-thread data;
/// idempotent.
void ensure_ode_ready();

inline void to_ode(const Eigen::Quaterniond& q, dQuaternion out) {
  out[0] = q.w();
  out[1] = q.x();
  out[2] = q.y();
  out[3] = q.z();
}

inline Eigen::Quaterniond from_ode(const dReal* q) { return {q[0], q[1], q[2], q[3]}; }

inline Eigen::Vector3d vec(const dReal* v) { return {v[0], v[1], v[2]}; }

/// Places a body at a pose.
inline void set_body_pose(dBodyID body, const Pose& pose) {
  dBodySetPosition(body, pose.position.x(), pose.position.y(), pose.position.z());
  dQuaternion q;
  to_ode(pose.orientation, q);
  dBodySetQuaternion(body, q);
}

/// The most contacts asked of dCollide for one pair of geoms.
constexpr int kMaxContacts = 8;

/// An angle wrapped to [-pi, pi].
inline double wrap_angle(double angle) { return std::remainder(angle, 2.0 * M_PI); }

/// A robot's body of MASS at POSE in WORLD; robots never sleep.
inline dBodyID make_robot_body(dWorldID world, const Pose& pose, const dMass& mass) {
  dBodyID body = dBodyCreate(world);
  dBodySetMass(body, &mass);
  set_body_pose(body, pose);
  dBodySetAutoDisableFlag(body, 0);
  return body;
}

inline Pose body_pose(dBodyID body) {
  return {vec(dBodyGetPosition(body)), from_ode(dBodyGetQuaternion(body))};
}

/// A body's pose as ODE holds it, bit for bit: x, y, z, then the quaternion w, x, y, z.
using ExactPose = std::array<dReal, 7>;

inline ExactPose exact_pose(dBodyID body) {
  const dReal* p = dBodyGetPosition(body);
  const dReal* q = dBodyGetQuaternion(body);
  return {p[0], p[1], p[2], q[0], q[1], q[2], q[3]};
}

/// Puts a pose into a body bit for bit. ODE's setters renormalize the quaternion they are
/// given, which moves one ODE normalized itself by an ulp or two; dBodyGetQuaternion and
/// dBodyGetRotation return the body's own storage, so the quaternion is written there after
/// the setter ran, and the rotation matrix made from it as ODE's step makes it (dQtoR).
inline void set_exact_pose(dBodyID body, const ExactPose& pose) {
  const dReal* q = pose.data() + 3;
  dBodySetQuaternion(body, q);
  auto* stored = const_cast<dReal*>(dBodyGetQuaternion(body));
  std::copy(q, q + 4, stored);
  dQtoR(stored, const_cast<dReal*>(dBodyGetRotation(body)));
  dBodySetPosition(body, pose[0], pose[1], pose[2]);  // and the geoms are told they moved
}

}  // namespace macsim::detail
