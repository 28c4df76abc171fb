// World: its complete state (by part), snapshots, restore, reset and the state hash. Each part's
// fields are listed once, in its archive() below; saving, reading back and hashing all use them.
#include "macsim/sim_core/world_state.h"

#include <xxhash.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_bounds.h"
#include "state_archive.h"
#include "world_internal.h"

namespace macsim {

// ---- the field lists ------------------------------------------------------------------------

template <class Ar>
void archive(Ar& ar, Pose& p) {
  ar(p.position, p.orientation);
}
template <class Ar>
void archive(Ar& ar, SourceLocation& s) {
  ar(s.file, s.line);
}
template <class Ar>
void archive(Ar& ar, ComponentSpec& c) {
  ar(c.shape, c.size, c.pose, c.color, c.texture);
}
template <class Ar>
void archive(Ar& ar, RampGeometry& r) {
  ar(r.width, r.height, r.angle);
}
template <class Ar>
void archive(Ar& ar, ObjectSpec& o) {
  ar(o.name, o.kind, o.portable, o.components, o.pose, o.density, o.material, o.magnetizable,
     o.frozen, o.user_data, o.user_color, o.user_shape, o.ramp, o.source);
}
template <class Ar>
void archive(Ar& ar, JointSpec& j) {
  ar(j.name, j.type, j.body1, j.body2, j.axis, j.anchor, j.lo, j.hi, j.max_force, j.velocity,
     j.source);
}
template <class Ar>
void archive(Ar& ar, DoorSpec& d) {
  ar(d.name, d.switch_base, d.switch_platform, d.switch_joint, d.frame, d.leaf, d.door_joint,
     d.source);
}
template <class Ar>
void archive(Ar& ar, DoorFlags& f) {
  ar(f.virtual_trigger, f.triggered, f.gap);
}
template <class Ar>
void archive(Ar& ar, BodyState& b) {
  ar(b.position, b.orientation, b.linear_velocity, b.angular_velocity, b.enabled,
     b.still_steps_left);
}
template <class Ar>
void archive(Ar& ar, PendingWrench& w) {
  ar(w.body, w.force, w.torque);
}
template <class Ar>
void archive(Ar& ar, WorldState& s) {
  ar(s.steps, s.random_seed, s.next_id, s.objects, s.joints, s.doors, s.door_flags, s.bodies,
     s.robots, s.body_order, s.wrenches);
}
template <class Ar>
void archive(Ar& ar, PhysicsSpec& p) {
  ar(p.step, p.gravity, p.solver_iterations, p.erp, p.cfm, p.seed);
}
template <class Ar>
void archive(Ar& ar, MaterialSpec& m) {
  ar(m.name, m.friction, m.bounce, m.bounce_velocity, m.density);
}
template <class Ar>
void archive(Ar& ar, RobotSpec& r) {
  ar(r.name, r.type, r.pose, r.encoder_rate, r.source);
}

namespace {
/// The values' bytes, in a buffer kept per thread (no allocation per call).
template <class... T>
const detail::ByteSink& serialized(const T&... values) {
  thread_local detail::StateWriter<detail::ByteSink> writer;
  writer.sink().clear();
  writer(values...);
  return writer.sink();
}
}  // namespace

std::vector<uint8_t> serialize(const WorldState& state) {
  const auto& bytes = serialized(state);
  return {bytes.data(), bytes.data() + bytes.size()};
}

WorldState deserialize(const std::vector<uint8_t>& bytes) {
  WorldState state;
  detail::StateReader reader(bytes);
  reader(state);
  if (!reader.at_end()) throw std::runtime_error("the snapshot has bytes after its end");
  return state;
}

uint64_t state_hash(const WorldState& state) {
  const auto& bytes = serialized(state);  // hashed in one pass: XXH3 is fastest on long input
  return XXH3_64bits(bytes.data(), bytes.size());
}

// ---- World's state -------------------------------------------------------------------------

WorldState World::state() const {
  WorldState s;
  s.steps = steps_;
  s.random_seed = random_seed_;
  s.next_id = table_->next_id();
  for (const auto& o : table_->objects()) s.objects.emplace_back(o->id, o->spec);
  for (const auto& j : table_->joints()) s.joints.push_back(j->spec);
  for (const auto& d : door_table_->doors()) {
    s.doors.push_back(d->spec);
    s.door_flags.push_back(d->flags);
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    s.bodies.push_back(detail::body_state(bodies_[i]));
    s.bodies.back().still_steps_left = still_steps_left_[i];
    const Eigen::Vector3d force = detail::vec(dBodyGetForce(bodies_[i]));
    const Eigen::Vector3d torque = detail::vec(dBodyGetTorque(bodies_[i]));
    if (!force.isZero(0) || !torque.isZero(0))
      s.wrenches.push_back({static_cast<uint32_t>(i), force, torque});
  }
  for (const auto& r : robots_) s.robots.push_back(r->save_state());
  s.body_order = body_order_;
  return s;
}

WorldSnapshot World::snapshot() const { return {fingerprint_, serialize(state())}; }

uint64_t World::state_hash() const { return macsim::state_hash(state()); }

uint64_t World::world_fingerprint() const {
  // The world as loaded: its settings, robots and initial state.
  const auto& bytes = serialized(spec_.name, spec_.physics, spec_.ground_friction, spec_.materials,
                                 spec_.robots, initial_);
  return XXH3_64bits(bytes.data(), bytes.size());
}

void World::rebuild(const WorldState& s, const std::vector<ObjectId>& fresh, bool fresh_robots) {
  clear_ode();
  table_->clear();
  door_table_->clear();
  for (const auto& [id, spec] : s.objects) table_->add(id, spec);
  for (const auto& spec : s.joints) table_->add_joint(spec);
  for (std::size_t i = 0; i < s.doors.size(); ++i) door_table_->add(s.doors[i], s.door_flags[i]);
  build(s.body_order);  // bodies at their reference poses: joints take their zero there
  // Bodies rebuilt fresh (a reset's) start their still steps anew, as loading left them.
  std::vector<int32_t> still_steps_left;
  std::vector<dBodyID> kept_bodies(s.bodies.size(), nullptr);  // by index in s.bodies
  std::size_t body = 0;
  for (const auto& [id, spec] : s.objects) {
    if (!spec.portable) continue;
    const bool kept = std::find(fresh.begin(), fresh.end(), id) == fresh.end();
    if (kept) {
      kept_bodies[body] = table_->find(id)->body;
      detail::set_body_state(kept_bodies[body], s.bodies[body]);
    }
    still_steps_left.push_back(kept ? s.bodies[body].still_steps_left : kStillStepsToSleep);
    ++body;
  }
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (fresh_robots) continue;
    for (dBodyID b : robots_[i]->bodies()) {
      still_steps_left.push_back(s.bodies[body].still_steps_left);
      kept_bodies[body] = b;
      detail::set_body_state(b, s.bodies[body++]);
    }
    robots_[i]->load_state(s.robots[i], [this](const std::string& object) -> dBodyID {
      const detail::ObjectRecord* o = table_->find_named(object);
      return o ? o->body : nullptr;
    });
  }
  // Asleep or awake as saved: a robot taking its state back (the magnet's hold made again)
  // may have woken a body it touches.
  for (std::size_t i = 0; i < kept_bodies.size(); ++i) {
    if (!kept_bodies[i]) continue;
    if (s.bodies[i].enabled) {
      dBodyEnable(kept_bodies[i]);
    } else {
      dBodyDisable(kept_bodies[i]);
    }
  }
  // What was added for the next step stays with the bodies kept (not with those made fresh).
  for (const auto& w : s.wrenches) {
    if (dBodyID b = w.body < kept_bodies.size() ? kept_bodies[w.body] : nullptr) {
      dBodySetForce(b, w.force.x(), w.force.y(), w.force.z());
      dBodySetTorque(b, w.torque.x(), w.torque.y(), w.torque.z());
    }
  }
  refresh_bodies();
  std::copy(still_steps_left.begin(), still_steps_left.end(), still_steps_left_.begin());
  steps_ = s.steps;
  table_->set_next_id(s.next_id);
  random_seed_ = s.random_seed;
  events_.clear();
}

namespace {
/// Why decoded state cannot be put into ODE, or nothing: what a file or a request could not
/// hold either (bounds), codes out of range, bodies that are not finite or not plausible.
std::optional<std::string> state_problem(const WorldState& s) {
  for (const auto& [id, o] : s.objects) {
    if (auto p = bounds::name_problem(o.name)) return p;
    if (static_cast<int>(o.kind) < 0 ||
        static_cast<int>(o.kind) > static_cast<int>(ObjectKind::DoorLeaf)) {
      return std::string("an object of an unknown kind");
    }
    if (auto p = bounds::object_problem(o)) return "'" + o.name + "': " + *p;
    // The world keeps every object's orientations unit (normalize_orientations, at load and
    // when made); one far from it would go into ODE's rotations as it is.
    auto unit = [](const Eigen::Quaterniond& q) { return std::abs(q.norm() - 1.0) <= 1e-9; };
    bool all_unit = unit(o.pose.orientation);
    for (const auto& c : o.components) all_unit = all_unit && unit(c.pose.orientation);
    if (!all_unit) return "'" + o.name + "': an orientation that is not a unit quaternion";
  }
  for (const auto& j : s.joints) {
    if (j.type != JointSpec::Type::Slider && j.type != JointSpec::Type::Hinge) {
      return std::string("a joint of an unknown type");
    }
    if (auto p = bounds::joint_problem(j)) return "joint '" + j.name + "': " + *p;
  }
  for (const auto& f : s.door_flags) {
    if (f.gap != DoorGap::Closed && f.gap != DoorGap::Half && f.gap != DoorGap::Open) {
      return std::string("a door with an unknown gap");
    }
  }
  for (const auto& b : s.bodies) {
    // The quaternion goes into ODE as it is (bit for bit): it must be a unit one already.
    if (!detail::plausible(b) || std::abs(b.orientation.norm() - 1.0) > 1e-9)
      return std::string("a body that is not plausible");
  }
  // What add_force and add_torque leave for the next step: many of bounds::kMaxForce at most,
  // each body once, in order, and only bodies that have some (as state() lists them).
  for (std::size_t i = 0; i < s.wrenches.size(); ++i) {
    const PendingWrench& w = s.wrenches[i];
    if (w.body >= s.bodies.size() || (i > 0 && w.body <= s.wrenches[i - 1].body) ||
        !w.force.allFinite() || !w.torque.allFinite() || w.force.norm() > 1e9 ||
        w.torque.norm() > 1e9 || (w.force.isZero(0) && w.torque.isZero(0))) {
      return std::string("a force or torque for the next step that is not plausible");
    }
  }
  return std::nullopt;
}

/// Whether the body order names each portable object and each of `robots` robots once, the
/// robots in their own order.
bool body_order_fits(const WorldState& s, std::size_t robots) {
  std::vector<int64_t> portable, named;
  for (const auto& [id, o] : s.objects) {
    if (o.portable) portable.push_back(id);
  }
  int64_t next_robot = -1;
  for (int64_t token : s.body_order) {
    if (token >= 0) {
      named.push_back(token);
    } else if (token == next_robot) {
      --next_robot;
    } else {
      return false;
    }
  }
  std::sort(portable.begin(), portable.end());
  std::sort(named.begin(), named.end());
  return static_cast<std::size_t>(-1 - next_robot) == robots && named == portable;
}
}  // namespace

Status World::restore(const WorldSnapshot& snapshot) {
  if (snapshot.fingerprint != fingerprint_) {
    return Status::error(ErrorCode::InvalidArgument,
                         "the snapshot is not one of this world (its fingerprint differs)");
  }
  WorldState s;
  try {
    s = deserialize(snapshot.bytes);
  } catch (const std::runtime_error& e) {
    return Status::error(ErrorCode::InvalidArgument, std::string("cannot restore: ") + e.what());
  }
  if (auto p = state_problem(s)) {
    return Status::error(ErrorCode::InvalidArgument, "cannot restore a damaged snapshot: " + *p);
  }
  if (s.robots.size() != robots_.size()) {
    return Status::error(ErrorCode::InvalidArgument, "the snapshot's parts do not fit this world");
  }
  if (!body_order_fits(s, robots_.size())) {
    return Status::error(ErrorCode::InvalidArgument,
                         "cannot restore a damaged snapshot: its body order does not name each "
                         "object's body and each robot once");
  }
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (auto p = robots_[i]->state_problem(s.robots[i])) {
      return Status::error(
          ErrorCode::InvalidArgument,
          "cannot restore a damaged snapshot: robot '" + robots_[i]->name() + "': " + *p);
    }
  }
  std::size_t portable = 0;
  for (const auto& object : s.objects) portable += object.second.portable ? 1 : 0;
  std::size_t robot_bodies = 0;
  for (const auto& r : robots_) robot_bodies += r->bodies().size();
  if (s.robots.size() != robots_.size() || s.bodies.size() != portable + robot_bodies ||
      s.door_flags.size() != s.doors.size()) {
    return Status::error(ErrorCode::InvalidArgument, "the snapshot's parts do not fit this world");
  }
  rebuild(s, {}, false);
  time_origin_ = {steps_, time_origin_.count + 1};
  return {};
}

void World::reset(ResetScope scope) {
  // What was loaded is rebuilt exactly as loading built it (at rest at its loaded pose);
  // only objects spawned since keep their current state.
  WorldState s = scope == ResetScope::Everything ? initial_ : state();
  std::vector<ObjectId> loaded;
  std::map<uint32_t, const ObjectSpec*> initial_specs;
  for (const auto& [id, spec] : initial_.objects) initial_specs[id] = &spec;
  for (auto& [id, spec] : s.objects) {
    auto initial = initial_specs.find(id);
    if (initial == initial_specs.end()) continue;
    spec.pose = initial->second->pose;
    loaded.push_back(id);
  }
  for (auto& joint : s.joints) {
    for (const auto& original : initial_.joints) {
      if (original.name == joint.name) joint.anchor = original.anchor;
    }
  }
  std::fill(s.door_flags.begin(), s.door_flags.end(), DoorFlags{});  // shut, switches released
  if (scope != ResetScope::Poses) {
    s.steps = 0;
    s.random_seed = initial_.random_seed;
  }
  rebuild(s, loaded, true);
  if (scope != ResetScope::Poses) time_origin_ = {steps_, time_origin_.count + 1};
}

}  // namespace macsim
