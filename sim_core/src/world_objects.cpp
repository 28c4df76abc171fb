// The world's object table (world_internal.h), and WorldObjects (world.h), its view: objects
// found by index, id, name or user data, and read: descriptions, poses, masses, inertia,
// textures, wrenches.
#include <algorithm>

#include "macsim/sim_core/world.h"
#include "world_internal.h"

namespace macsim {

namespace detail {

ObjectRecord& ObjectTable::add(ObjectId id, ObjectSpec spec) {
  auto record = std::make_unique<ObjectRecord>();
  record->id = id;
  record->spec = std::move(spec);
  objects_.push_back(std::move(record));
  return *objects_.back();
}

JointRecord& ObjectTable::add_joint(JointSpec spec) {
  joints_.push_back(std::make_unique<JointRecord>(JointRecord{std::move(spec), nullptr, 0.0}));
  return *joints_.back();
}

ObjectRecord* ObjectTable::find(ObjectId id) const {
  for (const auto& o : objects_) {
    if (o->id == id) return o.get();
  }
  return nullptr;
}

ObjectRecord* ObjectTable::find_named(const std::string& name) const {
  for (const auto& o : objects_) {
    if (o->spec.name == name) return o.get();
  }
  return nullptr;
}

Status ObjectTable::check(ObjectId id, const ObjectRecord*& out) const {
  out = find(id);
  if (!out)
    return Status::error(ErrorCode::UnknownObject, "no object with id " + std::to_string(id));
  return {};
}

std::optional<int> ObjectTable::index_of(ObjectId id) const {
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    if (objects_[i]->id == id) return static_cast<int>(i);
  }
  return std::nullopt;
}

JointRecord* ObjectTable::joint_named(const std::string& name) const {
  for (const auto& j : joints_) {
    if (j->spec.name == name) return j.get();
  }
  return nullptr;
}

void ObjectTable::erase(ObjectId id) {
  if (const auto index = index_of(id)) objects_.erase(objects_.begin() + *index);
}

void ObjectTable::erase_joint(const JointRecord* joint) {
  joints_.erase(std::find_if(joints_.begin(), joints_.end(),
                             [joint](const auto& j) { return j.get() == joint; }));
}

void ObjectTable::clear() {
  objects_.clear();
  joints_.clear();
}

ObjectState object_state(const ObjectRecord& o) {
  ObjectState state;
  state.pose = o.spec.pose;
  if (o.body) {
    const BodyState b = body_state(o.body);
    state.pose = Pose{b.position, b.orientation} * Pose{-o.com, Eigen::Quaterniond::Identity()};
    state.linear_velocity = b.linear_velocity;
    state.angular_velocity = b.angular_velocity;
  }
  return state;
}

Status free_body(const ObjectRecord& o, const std::string& what) {
  if (!o.body) {
    return Status::error(ErrorCode::NotApplicable, "'" + o.spec.name + "' is fixed: no " + what);
  }
  if (o.spec.frozen) {
    return Status::error(ErrorCode::NotApplicable, "'" + o.spec.name + "' is frozen: no " + what);
  }
  if (o.door >= 0) {
    return Status::error(ErrorCode::NotApplicable,
                         "'" + o.spec.name + "' is driven by its door's joint: no " + what);
  }
  return {};
}

}  // namespace detail

int WorldObjects::object_count() const { return static_cast<int>(table_.size()); }

std::optional<ObjectId> WorldObjects::object_at(int index) const {
  if (index < 0 || index >= object_count()) return std::nullopt;
  return table_.objects()[index]->id;
}

std::optional<int> WorldObjects::index_of(ObjectId id) const { return table_.index_of(id); }

std::optional<ObjectId> WorldObjects::find_object(const std::string& name) const {
  if (const detail::ObjectRecord* o = table_.find_named(name)) return o->id;
  return std::nullopt;
}

std::vector<ObjectId> WorldObjects::find_by_user_data(const std::string& user_data) const {
  std::vector<ObjectId> ids;
  for (const auto& o : table_.objects()) {
    if (o->spec.user_data == user_data) ids.push_back(o->id);
  }
  return ids;
}

std::vector<ObjectId> WorldObjects::object_ids() const {
  std::vector<ObjectId> ids;
  for (const auto& o : table_.objects()) ids.push_back(o->id);
  return ids;
}

const ObjectSpec* WorldObjects::object(ObjectId id) const {
  const detail::ObjectRecord* o = table_.find(id);
  return o ? &o->spec : nullptr;
}

Result<ObjectState> WorldObjects::object_state(ObjectId id) const {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return {s};
  return {{}, detail::object_state(*o)};
}

Result<double> WorldObjects::object_mass(ObjectId id) const {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return {s};
  if (!o->body)
    return {
        Status::error(ErrorCode::NotApplicable, "'" + o->spec.name + "' is fixed: it has no mass")};
  dMass m;
  dBodyGetMass(o->body, &m);
  return {{}, m.mass};
}

Result<Eigen::Matrix3d> WorldObjects::object_inertia(ObjectId id) const {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return {s};
  if (!o->body)
    return {Status::error(ErrorCode::NotApplicable,
                          "'" + o->spec.name + "' is fixed: it has no inertia")};
  dMass m;
  dBodyGetMass(o->body, &m);
  Eigen::Matrix3d inertia;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) inertia(r, c) = m.I[r * 4 + c];
  }
  return {{}, inertia};
}

Result<Eigen::Vector3d> WorldObjects::object_center_of_mass(ObjectId id) const {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return {s};
  return {{}, o->com};
}

Result<std::pair<int, std::string>> WorldObjects::object_texture(ObjectId id, int component) const {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return {s};
  if (component < 0 || component >= static_cast<int>(o->spec.components.size())) {
    return {detail::invalid_argument("component " + std::to_string(component) + " out of range")};
  }
  const std::string& file = o->spec.components[component].texture;
  if (file.empty()) return {{}, {0, ""}};
  auto found = std::find(textures_.begin(), textures_.end(), file);
  if (found == textures_.end()) {
    textures_.push_back(file);
    found = textures_.end() - 1;
  }
  return {{}, {static_cast<int>(found - textures_.begin()) + 1, file}};
}

Result<std::pair<Eigen::Vector3d, Eigen::Vector3d>> WorldObjects::object_wrench(ObjectId id) const {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return {s};
  if (!o->body) return {Status::error(ErrorCode::NotApplicable, "'" + o->spec.name + "' is fixed")};
  return {{}, {detail::vec(dBodyGetForce(o->body)), detail::vec(dBodyGetTorque(o->body))}};
}

Status WorldObjects::free_body(ObjectId id, const std::string& what) const {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
  return detail::free_body(*o, what);
}

}  // namespace macsim
