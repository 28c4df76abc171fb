// World: snapshot, restore, reset and the state hash.
#include <cstring>
#include <map>

#include "macsim/sim_core/world.h"
#include "world_internal.h"

namespace macsim {

namespace {

/// FNV-1a over raw bytes: cheap, stable, and equal for bit-identical states.
class Hasher {
 public:
  void add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= bytes[i];
      hash_ *= 1099511628211ull;
    }
  }
  template <class T>
  void add(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    add(&value, sizeof(T));
  }
  void add(const Eigen::Vector3d& v) { add(v.data(), 3 * sizeof(double)); }
  void add(const Eigen::Quaterniond& q) { add(q.coeffs().data(), 4 * sizeof(double)); }
  uint64_t value() const { return hash_; }

 private:
  uint64_t hash_ = 14695981039346656037ull;
};

/// Body states of a snapshot's portable objects, by id.
std::map<uint32_t, BodyState> object_bodies(const WorldSnapshot& s) {
  std::map<uint32_t, BodyState> out;
  std::size_t next = 0;
  for (const auto& [id, spec] : s.objects) {
    if (spec.portable) out[id] = s.bodies.at(next++);
  }
  return out;
}

std::size_t portable_count(const WorldSnapshot& s) {
  std::size_t n = 0;
  for (const auto& object : s.objects) n += object.second.portable ? 1 : 0;
  return n;
}

}  // namespace

WorldSnapshot World::snapshot() const {
  WorldSnapshot s{steps_, dRandGetSeed(), next_id_, {}, {}, {}, {}, {}, {}};
  for (const auto& o : objects_) s.objects.emplace_back(o->id, o->spec);
  for (const auto& j : joints_) s.joints.push_back(j->spec);
  for (const auto& d : doors_) {
    s.doors.push_back(d->spec);
    s.door_flags.push_back(static_cast<uint8_t>(d->virtual_trigger | (d->triggered << 1) |
                                                (static_cast<int>(d->gap) << 2)));
  }
  for (dBodyID body : bodies_) s.bodies.push_back(detail::body_state(body));
  for (const auto& r : robots_) s.robots.push_back(r->controller_state());
  return s;
}

Status World::restore(const WorldSnapshot& s) {
  const std::size_t expected_bodies = portable_count(s) + 7 * robots_.size();
  if (s.robots.size() != robots_.size() || s.bodies.size() != expected_bodies ||
      s.door_flags.size() != s.doors.size()) {
    return Status::error(ErrorCode::InvalidArgument, "the snapshot is not one of this world");
  }
  clear_ode();
  objects_.clear();
  for (const auto& [id, spec] : s.objects) {
    auto record = std::make_unique<Object>();
    record->id = id;
    record->spec = spec;
    objects_.push_back(std::move(record));
  }
  joints_.clear();
  for (const auto& spec : s.joints) joints_.push_back(std::make_unique<Joint>(Joint{spec, nullptr, 0.0}));
  doors_.clear();
  for (std::size_t i = 0; i < s.doors.size(); ++i) {
    auto record = std::make_unique<Door>();
    record->spec = s.doors[i];
    record->virtual_trigger = s.door_flags[i] & 1;
    record->triggered = (s.door_flags[i] >> 1) & 1;
    record->gap = static_cast<DoorGap>(s.door_flags[i] >> 2);
    doors_.push_back(std::move(record));
  }
  build();  // bodies at their reference poses: joints take their zero there
  for (std::size_t i = 0; i < bodies_.size(); ++i) detail::set_body_state(bodies_[i], s.bodies[i]);
  for (std::size_t i = 0; i < robots_.size(); ++i) robots_[i]->set_controller_state(s.robots[i]);
  refresh_bodies();
  steps_ = s.steps;
  next_id_ = s.next_id;
  dRandSetSeed(s.random_seed);
  events_.clear();
  return {};
}

void World::reset(ResetScope scope) {
  if (scope == ResetScope::Everything) {
    restore(initial_);
    return;
  }
  // Poses: what was loaded goes back to its loaded pose and rest; what was spawned stays.
  WorldSnapshot s = snapshot();
  const auto initial_bodies = object_bodies(initial_);
  auto current_bodies = object_bodies(s);
  std::map<uint32_t, const ObjectSpec*> initial_specs;
  for (const auto& [id, spec] : initial_.objects) initial_specs[id] = &spec;
  for (auto& [id, spec] : s.objects) {
    auto initial = initial_specs.find(id);
    if (initial == initial_specs.end()) continue;
    spec.pose = initial->second->pose;
    if (auto body = initial_bodies.find(id); body != initial_bodies.end()) current_bodies[id] = body->second;
  }
  for (auto& joint : s.joints) {
    for (const auto& original : initial_.joints) {
      if (original.name == joint.name) joint.anchor = original.anchor;
    }
  }
  s.bodies.clear();
  for (const auto& [id, spec] : s.objects) {
    if (spec.portable) s.bodies.push_back(current_bodies.at(id));
  }
  const std::size_t robot_bodies = 7 * robots_.size();
  s.bodies.insert(s.bodies.end(), initial_.bodies.end() - robot_bodies, initial_.bodies.end());
  s.robots = initial_.robots;
  if (scope == ResetScope::PosesAndTime) {
    s.steps = 0;
    s.random_seed = initial_.random_seed;
  }
  restore(s);
}

uint64_t World::state_hash() const {
  Hasher h;
  h.add(steps_);
  h.add(dRandGetSeed());
  std::size_t body = 0;
  for (const auto& o : objects_) {
    h.add(o->id);
    h.add(o->spec.pose.position);
    h.add(o->spec.pose.orientation);
    if (!o->body) continue;
    const BodyState b = detail::body_state(bodies_[body++]);
    h.add(b.position);
    h.add(b.orientation);
    h.add(b.linear_velocity);
    h.add(b.angular_velocity);
  }
  for (const auto& r : robots_) {
    for (dBodyID b : r->bodies()) {
      const BodyState s = detail::body_state(b);
      h.add(s.position);
      h.add(s.orientation);
      h.add(s.linear_velocity);
      h.add(s.angular_velocity);
    }
    const auto& c = r->controller_state();
    h.add(c.commanded);
    h.add(c.active);
    h.add(c.last_command_time);
    h.add(c.encoder_angle);
    h.add(c.frames);
    const PlanarOdometry odom = c.odometry.estimate();
    h.add(odom);
  }
  for (const auto& d : doors_) h.add(static_cast<uint8_t>(d->virtual_trigger | (d->triggered << 1)));
  return h.value();
}

}  // namespace macsim
