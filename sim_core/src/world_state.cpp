// World: snapshot, restore, reset and the state hash.
#include <algorithm>
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

std::size_t portable_count(const WorldSnapshot& s) {
  std::size_t n = 0;
  for (const auto& object : s.objects) n += object.second.portable ? 1 : 0;
  return n;
}

}  // namespace

WorldSnapshot World::snapshot() const {
  WorldSnapshot s{steps_, random_seed_, next_id_, {}, {}, {}, {}, {}, {}};
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

void World::rebuild(const WorldSnapshot& s, const std::vector<ObjectId>& fresh, bool fresh_robots) {
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
  std::size_t body = 0;
  for (const auto& [id, spec] : s.objects) {
    if (!spec.portable) continue;
    if (std::find(fresh.begin(), fresh.end(), id) == fresh.end()) {
      detail::set_body_state(find(id)->body, s.bodies[body]);
    }
    ++body;
  }
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (fresh_robots) continue;
    for (dBodyID b : robots_[i]->bodies()) detail::set_body_state(b, s.bodies[body++]);
    robots_[i]->set_controller_state(s.robots[i]);
    if (!s.robots[i].held_object.empty()) {
      if (auto held = find_object(s.robots[i].held_object)) robots_[i]->reattach(find(*held)->body);
    }
  }
  refresh_bodies();
  steps_ = s.steps;
  next_id_ = s.next_id;
  random_seed_ = s.random_seed;
  events_.clear();
}

Status World::restore(const WorldSnapshot& s) {
  std::size_t robot_bodies = 0;
  for (const auto& r : robots_) robot_bodies += r->bodies().size();
  const std::size_t expected_bodies = portable_count(s) + robot_bodies;
  if (s.robots.size() != robots_.size() || s.bodies.size() != expected_bodies ||
      s.door_flags.size() != s.doors.size()) {
    return Status::error(ErrorCode::InvalidArgument, "the snapshot is not one of this world");
  }
  rebuild(s, {}, false);
  return {};
}

void World::reset(ResetScope scope) {
  // What was loaded is rebuilt exactly as loading built it (at rest at its loaded pose);
  // only objects spawned since keep their current state.
  WorldSnapshot s = scope == ResetScope::Everything ? initial_ : snapshot();
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
  std::fill(s.door_flags.begin(), s.door_flags.end(), 0);  // doors shut, switches released
  if (scope != ResetScope::Poses) {
    s.steps = 0;
    s.random_seed = initial_.random_seed;
  }
  rebuild(s, loaded, true);
}

uint64_t World::state_hash() const {
  Hasher h;
  h.add(steps_);
  h.add(random_seed_);
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
