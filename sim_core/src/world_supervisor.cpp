// World: the supervisor operations (find, read, create, destroy, change objects and doors).
// Every operation checks its arguments before touching ODE: on error the world is unchanged.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "macsim/sim_core/data_roots.h"
#include "macsim/sim_core/texture.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_bounds.h"
#include "macsim/sim_core/world_loader.h"
#include "world_internal.h"

namespace macsim {

namespace {

Status invalid(const std::string& message) {
  return Status::error(ErrorCode::InvalidArgument, message);
}

/// Why a pose is unusable (out of bounds, not finite, a zero quaternion), or nothing.
std::optional<std::string> pose_problem(const Pose& p) {
  if (auto problem = bounds::position_problem(p.position)) return problem;
  return bounds::orientation_problem(p.orientation);
}

}  // namespace

// ---- finding ---------------------------------------------------------------------------

World::Object* World::find(ObjectId id) const {
  for (const auto& o : objects_) {
    if (o->id == id) return o.get();
  }
  return nullptr;
}

Status World::check_object_id(ObjectId id, const Object*& out) const {
  out = find(id);
  if (!out)
    return Status::error(ErrorCode::UnknownObject, "no object with id " + std::to_string(id));
  return {};
}

std::optional<ObjectId> World::object_at(int index) const {
  if (index < 0 || index >= object_count()) return std::nullopt;
  return objects_[index]->id;
}

std::optional<int> World::index_of(ObjectId id) const {
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    if (objects_[i]->id == id) return static_cast<int>(i);
  }
  return std::nullopt;
}

std::optional<ObjectId> World::find_object(const std::string& name) const {
  for (const auto& o : objects_) {
    if (o->spec.name == name) return o->id;
  }
  return std::nullopt;
}

std::vector<ObjectId> World::find_by_user_data(const std::string& user_data) const {
  std::vector<ObjectId> ids;
  for (const auto& o : objects_) {
    if (o->spec.user_data == user_data) ids.push_back(o->id);
  }
  return ids;
}

std::vector<ObjectId> World::object_ids() const {
  std::vector<ObjectId> ids;
  for (const auto& o : objects_) ids.push_back(o->id);
  return ids;
}

// ---- reading ---------------------------------------------------------------------------

const ObjectSpec* World::object(ObjectId id) const {
  const Object* o = find(id);
  return o ? &o->spec : nullptr;
}

Result<ObjectState> World::object_state(ObjectId id) const {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return {s};
  ObjectState state;
  state.pose = o->spec.pose;
  if (o->body) {
    const BodyState b = detail::body_state(o->body);
    state.pose = Pose{b.position, b.orientation} * Pose{-o->com, Eigen::Quaterniond::Identity()};
    state.linear_velocity = b.linear_velocity;
    state.angular_velocity = b.angular_velocity;
  }
  return {{}, state};
}

Result<double> World::object_mass(ObjectId id) const {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return {s};
  if (!o->body)
    return {
        Status::error(ErrorCode::NotApplicable, "'" + o->spec.name + "' is fixed: it has no mass")};
  dMass m;
  dBodyGetMass(o->body, &m);
  return {{}, m.mass};
}

Result<Eigen::Matrix3d> World::object_inertia(ObjectId id) const {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return {s};
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

Result<Eigen::Vector3d> World::object_center_of_mass(ObjectId id) const {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return {s};
  return {{}, o->com};
}

Result<std::pair<int, std::string>> World::object_texture(ObjectId id, int component) const {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return {s};
  if (component < 0 || component >= static_cast<int>(o->spec.components.size())) {
    return {invalid("component " + std::to_string(component) + " out of range")};
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

Result<std::pair<Eigen::Vector3d, Eigen::Vector3d>> World::object_wrench(ObjectId id) const {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return {s};
  if (!o->body) return {Status::error(ErrorCode::NotApplicable, "'" + o->spec.name + "' is fixed")};
  return {{}, {detail::vec(dBodyGetForce(o->body)), detail::vec(dBodyGetTorque(o->body))}};
}

// ---- creating and destroying -------------------------------------------------------------

namespace {

/// LimitReached: `adding` more objects would pass the world's cap.
Status objects_capped(std::size_t count, std::size_t adding, std::size_t cap) {
  return Status::error(ErrorCode::LimitReached,
                       "the world holds " + std::to_string(count) + " objects and may hold " +
                           std::to_string(cap) + " (macsim --max-objects); " +
                           std::to_string(adding) +
                           " more would pass the cap: destroy some first, or raise the cap");
}

}  // namespace

Status World::validate_new_object(ObjectSpec& spec) const {
  if (objects_.size() >= max_objects_) return objects_capped(objects_.size(), 1, max_objects_);
  if (spec.kind != ObjectKind::Object && spec.kind != ObjectKind::Wall &&
      spec.kind != ObjectKind::Ramp) {
    return invalid("door and switch parts are created with import_environment(), not alone");
  }
  if (spec.ramp) {
    spec.kind = ObjectKind::Ramp;
    spec.portable = false;
    ComponentSpec box = spec.ramp->box();
    if (!spec.components.empty()) {
      box.color = spec.components.front().color;
      box.texture = spec.components.front().texture;
    }
    spec.components = {box};
  } else if (spec.kind == ObjectKind::Ramp) {
    return invalid("a ramp needs its ramp geometry (width, height, angle)");
  }
  if (auto p = bounds::object_problem(spec)) return invalid(*p);
  normalize_orientations(spec);
  for (auto& c : spec.components) {
    if (!c.texture.empty()) {
      if (Status s = texture_status(c.texture); !s.ok()) return s;
      c.texture = files_->identity(c.texture);  // the file checked, in one spelling
    }
  }
  if (!spec_.material(spec.material)) return invalid("unknown material '" + spec.material + "'");
  if (!spec.name.empty()) {
    if (auto p = bounds::name_problem(spec.name)) return invalid(*p);
  }
  if (!spec.name.empty() && find_object(spec.name)) {
    return invalid("an object named '" + spec.name + "' exists already");
  }
  return {};
}

Result<ObjectId> World::create_object(ObjectSpec spec, PenetrationPolicy policy) {
  if (Status s = validate_new_object(spec); !s.ok()) return {s};
  const ObjectId id = next_id_++;
  if (spec.name.empty()) spec.name = "object_" + std::to_string(id);
  Object& o = add_object_record(id, std::move(spec));
  build_object(o);
  Status status;
  status.penetrated = penetrations(o);
  if (!status.penetrated.empty()) {
    if (policy == PenetrationPolicy::Refuse) {
      Status refused =
          Status::error(ErrorCode::Penetration,
                        "'" + o.spec.name + "' would penetrate " + status.penetrated.front());
      destroy_ode_object(o);
      objects_.pop_back();  // `o` is gone from here on
      next_id_ = id;        // the world as it was, its next id included
      return {refused};
    }
    emit(WorldEvent::Type::Penetration, o.spec.name, "created inside " + status.penetrated.front());
  }
  structure_changed();
  return {status, o.id};
}

Status World::add_spec_objects(WorldSpec fragment, std::vector<ObjectId>* ids) {
  if (!fragment.robots.empty()) return invalid("robots cannot be added to a running world");
  if (objects_.size() + fragment.objects.size() > max_objects_) {
    return objects_capped(objects_.size(), fragment.objects.size(), max_objects_);
  }
  for (const auto& object : fragment.objects) {
    if (find_object(object.name))
      return invalid("an object named '" + object.name + "' exists already");
  }
  for (const auto& m : fragment.materials) {
    if (!spec_.material(m.name)) spec_.materials.push_back(m);
  }
  std::vector<Object*> added;
  for (auto& object : fragment.objects)
    added.push_back(&add_object_record(next_id_++, std::move(object)));
  std::vector<Joint*> new_joints;
  for (auto& joint : fragment.joints) new_joints.push_back(&add_joint_record(std::move(joint)));
  for (auto& door : fragment.doors) add_door_record(std::move(door), {});
  wire_doors();
  for (Object* o : added) {
    build_object(*o);
    if (ids) ids->push_back(o->id);
  }
  for (Joint* j : new_joints) build_joint(*j);
  structure_changed();
  return {};
}

Result<std::vector<ObjectId>> World::import_environment(const std::string& file,
                                                        const std::string& id, const Pose& pose) {
  if (auto p = pose_problem(pose)) return {invalid("the import's " + *p)};
  if (auto p = bounds::id_problem(id)) return {invalid("import id: " + *p)};
  WorldSpec fragment;
  try {
    fragment = load_environment_file(file, id, spec_.materials, {}, *files_);
  } catch (const WorldFileError& e) {
    return {Status::error(ErrorCode::BadFile, e.what())};
  } catch (const FileRefused& e) {  // outside the data roots, a special file, too large
    return {Status::error(ErrorCode::BadFile, e.what())};
  } catch (const std::exception& e) {  // e.g. a path the file system refuses
    return {Status::error(ErrorCode::BadFile, "cannot import '" + file + "': " + e.what())};
  }
  return add_environment(std::move(fragment), pose);
}

Result<std::vector<ObjectId>> World::add_environment(WorldSpec fragment, const Pose& pose) {
  if (auto p = pose_problem(pose)) return {invalid("the environment's " + *p)};
  Pose frame = pose;
  frame.orientation.normalize();
  for (auto& object : fragment.objects) object.pose = frame * object.pose;
  for (auto& joint : fragment.joints) {
    joint.axis = frame.orientation * joint.axis;
    joint.anchor = frame.position + frame.orientation * joint.anchor;
  }
  try {  // placed: still within bounds?
    bounds::check_world(fragment);
  } catch (const WorldFileError& e) {
    return {invalid(e.what())};
  }
  std::vector<ObjectId> ids;
  if (Status s = add_spec_objects(std::move(fragment), &ids); !s.ok()) return {s};
  return {{}, ids};
}

void World::erase_object(ObjectId id) {
  Object* o = find(id);
  if (!o) return;
  for (auto it = joints_.begin(); it != joints_.end();) {
    if ((*it)->spec.body1 == o->spec.name || (*it)->spec.body2 == o->spec.name) {
      if ((*it)->joint) dJointDestroy((*it)->joint);
      it = joints_.erase(it);
    } else {
      ++it;
    }
  }
  destroy_ode_object(*o);
  objects_.erase(objects_.begin() + *index_of(id));
}

Status World::destroy_object(ObjectId id) {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return s;
  if (o->door >= 0) {
    // A door part takes its whole door-switch structure with it.
    const int door = o->door;
    const DoorSpec parts = doors_[door]->spec;
    for (const std::string* part :
         {&parts.leaf, &parts.frame, &parts.switch_platform, &parts.switch_base}) {
      if (auto part_id = find_object(*part)) erase_object(*part_id);
    }
    doors_.erase(doors_.begin() + door);
    wire_doors();
    for (auto& other : objects_) {  // the later doors' indices moved down: so do their groups
      if (other->door >= door) other->tag.group = 1'000'000 + other->door;
    }
  } else {
    erase_object(id);
  }
  structure_changed();
  return {};
}

int World::destroy_matching(const std::function<bool(const ObjectSpec&)>& match) {
  int destroyed = 0;
  for (bool again = true; again;) {
    again = false;
    for (const auto& o : objects_) {
      if (match(o->spec)) {
        const int before = object_count();
        destroy_object(o->id);
        destroyed += before - object_count();
        again = true;
        break;
      }
    }
  }
  return destroyed;
}

int World::destroy_objects(const std::string& user_data) {
  return destroy_matching([&](const ObjectSpec& s) { return s.user_data == user_data; });
}

int World::destroy_all_objects() {
  return destroy_matching([](const ObjectSpec&) { return true; });
}

int World::destroy_all_portable_objects() {
  return destroy_matching([](const ObjectSpec& s) { return s.portable; });
}

int World::destroy_all_fixed_objects() {
  return destroy_matching([](const ObjectSpec& s) { return !s.portable; });
}

// ---- changing --------------------------------------------------------------------------

void World::rebuild_object(Object& o, const ObjectSpec& spec, const ObjectState& state) {
  std::vector<Joint*> attached;
  for (auto& j : joints_) {
    if (j->joint && (j->spec.body1 == o.spec.name || j->spec.body2 == o.spec.name)) {
      j->position = j->spec.type == JointSpec::Type::Slider ? dJointGetSliderPosition(j->joint)
                                                            : dJointGetHingeAngle(j->joint);
      dJointDestroy(j->joint);
      j->joint = nullptr;
      attached.push_back(j.get());
    }
  }
  destroy_ode_object(o);
  o.spec = spec;
  if (attached.empty()) {
    o.spec.pose = state.pose;  // a jointed body keeps its joint's zero as its reference pose
  }
  build_object(o);
  if (o.body) {
    const Pose body = state.pose * Pose{o.com, Eigen::Quaterniond::Identity()};
    detail::set_body_state(
        o.body, {body.position, body.orientation, state.linear_velocity, state.angular_velocity});
  }
  for (Joint* j : attached) build_joint(*j);
}

Status World::change_object(ObjectId id, PenetrationPolicy policy,
                            const std::function<Status(ObjectSpec&, Pose&)>& change) {
  const Object* found = nullptr;
  if (Status s = check_object_id(id, found); !s.ok()) return s;
  Object& o = *find(id);
  const ObjectSpec old_spec = o.spec;
  const ObjectState old_state = object_state(id).value;
  ObjectSpec spec = o.spec;
  Pose pose = old_state.pose;
  if (Status s = change(spec, pose); !s.ok()) return s;
  ObjectSpec placed = spec;  // the changed object where it will stand: within bounds?
  placed.pose = pose;
  if (auto p = bounds::object_problem(placed)) return invalid(*p);
  ObjectState state = old_state;
  state.pose = pose;
  rebuild_object(o, spec, state);
  Status status;
  status.penetrated = penetrations(o);
  if (!status.penetrated.empty()) {
    if (policy == PenetrationPolicy::Refuse) {
      rebuild_object(o, old_spec, old_state);
      structure_changed();
      Status refused =
          Status::error(ErrorCode::Penetration, "refused: '" + o.spec.name + "' would penetrate '" +
                                                    status.penetrated.front() + "'");
      refused.penetrated = status.penetrated;
      return refused;
    }
    emit(WorldEvent::Type::Penetration, o.spec.name, "penetrates " + status.penetrated.front());
  }
  structure_changed();
  return status;
}

Status World::set_pose(ObjectId id, const Pose& pose, PenetrationPolicy policy) {
  if (auto p = pose_problem(pose)) return invalid(*p);
  const Object* o = find(id);
  if (o && o->door >= 0) {
    return Status::error(ErrorCode::NotApplicable,
                         "'" + o->spec.name + "' is part of door '" + doors_[o->door]->spec.name +
                             "': move it with set_door_position or set_switch_position");
  }
  Pose target = pose;
  target.orientation.normalize();
  return change_object(id, policy, [&](ObjectSpec&, Pose& p) {
    p = target;
    return Status{};
  });
}

Status World::set_position(ObjectId id, const Eigen::Vector3d& position, PenetrationPolicy policy) {
  auto state = object_state(id);
  if (!state.ok()) return state.status;
  Pose pose = state.value.pose;
  pose.position = position;
  return set_pose(id, pose, policy);
}

Status World::set_orientation(ObjectId id, const Eigen::Quaterniond& orientation,
                              PenetrationPolicy policy) {
  auto state = object_state(id);
  if (!state.ok()) return state.status;
  Pose pose = state.value.pose;
  pose.orientation = orientation;
  return set_pose(id, pose, policy);
}

Status World::resize_component(ObjectId id, int component, Shape shape, const Eigen::Vector3d& size,
                               PenetrationPolicy policy) {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return s;
  if (o->spec.kind == ObjectKind::Ramp) {
    return Status::error(ErrorCode::WrongGeometry,
                         "'" + o->spec.name + "' is a ramp: change it with set_ramp");
  }
  if (component < 0 || component >= static_cast<int>(o->spec.components.size())) {
    return invalid("'" + o->spec.name + "' has no component " + std::to_string(component) +
                   " (it has " + std::to_string(o->spec.components.size()) + ")");
  }
  const Shape actual = o->spec.components[component].shape;
  if (actual != shape) {
    return Status::error(ErrorCode::WrongGeometry,
                         "component " + std::to_string(component) + " of '" + o->spec.name +
                             "' is a " + shape_name(actual) + ", not a " + shape_name(shape));
  }
  const bool wall = o->spec.kind == ObjectKind::Wall;
  return change_object(id, policy, [&](ObjectSpec& spec, Pose&) {
    spec.components[component].size = size;
    if (wall) spec.components[component].pose.position.z() = size.z() / 2;  // stays on the floor
    return Status{};
  });
}

Status World::set_box_size(ObjectId id, int component, const Eigen::Vector3d& size,
                           PenetrationPolicy policy) {
  return resize_component(id, component, Shape::Box, size, policy);
}

Status World::set_cylinder_size(ObjectId id, int component, double radius, double height,
                                PenetrationPolicy policy) {
  return resize_component(id, component, Shape::Cylinder, {radius, 0.0, height}, policy);
}

Status World::set_sphere_size(ObjectId id, int component, double radius, PenetrationPolicy policy) {
  return resize_component(id, component, Shape::Sphere, {radius, 0.0, 0.0}, policy);
}

Status World::set_ramp(ObjectId id, const RampGeometry& ramp, PenetrationPolicy policy) {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return s;
  if (o->spec.kind != ObjectKind::Ramp) {
    return Status::error(ErrorCode::WrongGeometry, "'" + o->spec.name + "' is not a ramp");
  }
  return change_object(id, policy, [&](ObjectSpec& spec, Pose&) {
    ComponentSpec box = ramp.box();
    box.color = spec.components.front().color;
    box.texture = spec.components.front().texture;
    spec.components = {box};
    spec.ramp = ramp;
    return Status{};
  });
}

Status World::set_color(ObjectId id, const Color& color, int component) {
  const Object* found = nullptr;
  if (Status s = check_object_id(id, found); !s.ok()) return s;
  for (float channel : color) {
    if (!std::isfinite(channel) || channel < 0 || channel > 1)
      return invalid("colour channels must lie in [0, 1]");
  }
  Object& o = *find(id);
  if (component < -1 || component >= static_cast<int>(o.spec.components.size())) {
    return invalid("'" + o.spec.name + "' has no component " + std::to_string(component));
  }
  for (int i = 0; i < static_cast<int>(o.spec.components.size()); ++i) {
    if (component == -1 || component == i) o.spec.components[i].color = color;
  }
  return {};
}

Status World::texture_status(const std::string& path) const {
  try {
    if (auto p = texture_problem(path, *files_)) return Status::error(ErrorCode::BadTexture, *p);
  } catch (const FileRefused& refused) {
    return Status::error(ErrorCode::BadFile, refused.what());
  }
  return {};
}

void World::set_data_roots(std::shared_ptr<const DataRoots> roots) {
  files_ = roots ? std::move(roots) : DataRoots::anywhere();
}

Status World::set_texture(ObjectId id, const std::string& path, int component) {
  const Object* found = nullptr;
  if (Status s = check_object_id(id, found); !s.ok()) return s;
  Object& o = *find(id);
  if (component < -1 || component >= static_cast<int>(o.spec.components.size())) {
    return invalid("'" + o.spec.name + "' has no component " + std::to_string(component));
  }
  std::string file;
  if (!path.empty()) {
    if (Status s = texture_status(path); !s.ok()) return s;
    file = files_->identity(path);  // the file checked, in one spelling
  }
  for (int i = 0; i < static_cast<int>(o.spec.components.size()); ++i) {
    if (component == -1 || component == i) o.spec.components[i].texture = file;
  }
  return {};
}

Status World::set_mass(ObjectId id, double mass) {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return s;
  if (!std::isfinite(mass) || mass <= 0) return invalid("mass must be finite and positive");
  if (!o->spec.portable) {
    return Status::error(ErrorCode::NotApplicable,
                         "'" + o->spec.name + "' is fixed: it has no mass");
  }
  return change_object(id, PenetrationPolicy::Allow, [&](ObjectSpec& spec, Pose&) {
    spec.density = mass / spec.volume();
    return Status{};
  });
}

Status World::set_density(ObjectId id, double density) {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return s;
  if (!std::isfinite(density) || density <= 0)
    return invalid("density must be finite and positive");
  if (!o->spec.portable) {
    return Status::error(ErrorCode::NotApplicable,
                         "'" + o->spec.name + "' is fixed: it has no density");
  }
  return change_object(id, PenetrationPolicy::Allow, [&](ObjectSpec& spec, Pose&) {
    spec.density = density;
    return Status{};
  });
}

Status World::free_body(ObjectId id, const std::string& what) const {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return s;
  if (!o->body) {
    return Status::error(ErrorCode::NotApplicable, "'" + o->spec.name + "' is fixed: no " + what);
  }
  if (o->spec.frozen) {
    return Status::error(ErrorCode::NotApplicable, "'" + o->spec.name + "' is frozen: no " + what);
  }
  if (o->door >= 0) {
    return Status::error(ErrorCode::NotApplicable,
                         "'" + o->spec.name + "' is driven by its door's joint: no " + what);
  }
  return {};
}

Status World::dynamic_body(ObjectId id, const Eigen::Vector3d& value, const char* what,
                           dxBody*& body) const {
  const Object* o = nullptr;
  if (Status s = check_object_id(id, o); !s.ok()) return s;
  const bool angular = std::string(what) == "angular velocity";
  const double max = std::string(what) == "linear velocity" ? bounds::kMaxSpeed
                     : angular                              ? bounds::kMaxAngularSpeed
                                                            : bounds::kMaxForce;
  if (auto p = bounds::magnitude_problem(value, max, what)) return invalid(*p);
  if (Status s = free_body(id, what); !s.ok()) return s;
  body = o->body;
  dBodyEnable(body);  // wake it: it is about to move
  return {};
}

Status World::set_linear_velocity(ObjectId id, const Eigen::Vector3d& v) {
  dBodyID body = nullptr;
  if (Status s = dynamic_body(id, v, "linear velocity", body); !s.ok()) return s;
  dBodySetLinearVel(body, v.x(), v.y(), v.z());
  return {};
}

Status World::set_angular_velocity(ObjectId id, const Eigen::Vector3d& w) {
  dBodyID body = nullptr;
  if (Status s = dynamic_body(id, w, "angular velocity", body); !s.ok()) return s;
  dBodySetAngularVel(body, w.x(), w.y(), w.z());
  return {};
}

Status World::add_force(ObjectId id, const Eigen::Vector3d& f) {
  dBodyID body = nullptr;
  if (Status s = dynamic_body(id, f, "force", body); !s.ok()) return s;
  dBodyAddForce(body, f.x(), f.y(), f.z());
  return {};
}

Status World::add_torque(ObjectId id, const Eigen::Vector3d& t) {
  dBodyID body = nullptr;
  if (Status s = dynamic_body(id, t, "torque", body); !s.ok()) return s;
  dBodyAddTorque(body, t.x(), t.y(), t.z());
  return {};
}

Status World::set_frozen(ObjectId id, bool frozen) {
  const Object* found = nullptr;
  if (Status s = check_object_id(id, found); !s.ok()) return s;
  Object& o = *find(id);
  if (!o.body)
    return Status::error(ErrorCode::NotApplicable, "'" + o.spec.name + "' is fixed already");
  if (o.door >= 0)
    return Status::error(ErrorCode::NotApplicable, "'" + o.spec.name + "' is part of a door");
  o.spec.frozen = frozen;
  if (frozen) {
    dBodySetLinearVel(o.body, 0, 0, 0);
    dBodySetAngularVel(o.body, 0, 0, 0);
    dBodySetKinematic(o.body);
  } else {
    dBodySetDynamic(o.body);
    dBodyEnable(o.body);
  }
  return {};
}

Status World::set_magnetizable(ObjectId id, bool magnetizable) {
  const Object* found = nullptr;
  if (Status s = check_object_id(id, found); !s.ok()) return s;
  find(id)->spec.magnetizable = magnetizable;
  return {};
}

Status World::set_user_data(ObjectId id, const std::string& user_data) {
  const Object* found = nullptr;
  if (Status s = check_object_id(id, found); !s.ok()) return s;
  find(id)->spec.user_data = user_data;
  return {};
}

Status World::set_user_labels(ObjectId id, int user_color, int user_shape) {
  const Object* found = nullptr;
  if (Status s = check_object_id(id, found); !s.ok()) return s;
  find(id)->spec.user_color = user_color;
  find(id)->spec.user_shape = user_shape;
  return {};
}

// ---- doors -----------------------------------------------------------------------------

std::optional<int> World::find_door(const std::string& name) const {
  for (std::size_t i = 0; i < doors_.size(); ++i) {
    if (doors_[i]->spec.name == name) return static_cast<int>(i);
  }
  return std::nullopt;
}

Result<int> World::get_door_by_name(const std::string& name) const {
  if (const auto door = find_door(name)) return {{}, *door};
  return {Status::error(ErrorCode::UnknownObject, "no door named '" + name + "' (there are " +
                                                      std::to_string(door_count()) + ")")};
}

Status World::check_door(int door) const {
  if (door < 0 || door >= door_count()) {
    return Status::error(ErrorCode::UnknownObject, "no door with index " + std::to_string(door) +
                                                       " (there are " +
                                                       std::to_string(door_count()) + ")");
  }
  return {};
}

const std::string& World::door_name(int door) const { return doors_.at(door)->spec.name; }

Result<DoorState> World::door_state(int door) const {
  if (Status s = check_door(door); !s.ok()) return {s};
  return {{}, door_state_of(*doors_[door])};
}

Result<DoorParts> World::door_parts(int door) const {
  if (Status s = check_door(door); !s.ok()) return {s};
  const DoorSpec& s = doors_[door]->spec;
  DoorParts parts;
  parts.leaf = find_object(s.leaf).value_or(0);
  parts.frame = find_object(s.frame).value_or(0);
  parts.platform = find_object(s.switch_platform);
  parts.base = find_object(s.switch_base);
  return {{}, parts};
}

Status World::set_switch_triggered(int door, bool triggered) {
  if (Status s = check_door(door); !s.ok()) return s;
  doors_[door]->flags.virtual_trigger = triggered;
  return {};
}

Status World::move_door_part(int door, bool leaf, const Eigen::Vector3d& position) {
  if (Status s = check_door(door); !s.ok()) return s;
  if (auto p = bounds::position_problem(position)) return invalid(*p);
  Door& d = *doors_[door];
  const std::string moving_name = leaf ? d.spec.leaf : d.spec.switch_platform;
  const std::string fixed_name = leaf ? d.spec.frame : d.spec.switch_base;
  Joint* joint = leaf ? d.door_joint : d.switch_joint;
  const auto moving = find_object(moving_name);
  if (!moving || !joint) {
    return Status::error(ErrorCode::NotApplicable, "door '" + d.spec.name + "' has no switch");
  }
  const Eigen::Vector3d delta = position - object_state(*moving).value.pose.position;
  // The moving part, its fixed part and their joint move together.
  joint->position = joint->spec.type == JointSpec::Type::Slider
                        ? dJointGetSliderPosition(joint->joint)
                        : dJointGetHingeAngle(joint->joint);
  dJointDestroy(joint->joint);
  joint->joint = nullptr;
  joint->spec.anchor += delta;
  Status status;
  for (const std::string* name : {&moving_name, &fixed_name}) {
    auto id = find_object(*name);
    if (!id) continue;
    Object& o = *find(*id);
    ObjectState state = object_state(*id).value;
    state.pose.position += delta;
    o.spec.pose.position += delta;
    const ObjectSpec spec = o.spec;
    destroy_ode_object(o);
    o.spec = spec;
    build_object(o);
    if (o.body) {
      const Pose body = state.pose * Pose{o.com, Eigen::Quaterniond::Identity()};
      detail::set_body_state(
          o.body, {body.position, body.orientation, state.linear_velocity, state.angular_velocity});
    }
    for (const auto& hit : penetrations(o)) status.penetrated.push_back(hit);
  }
  build_joint(*joint);
  structure_changed();
  if (!status.penetrated.empty()) {
    emit(WorldEvent::Type::Penetration, d.spec.name, "moved into " + status.penetrated.front());
  }
  return status;
}

Status World::set_door_position(int door, const Eigen::Vector3d& position) {
  return move_door_part(door, true, position);
}

Status World::set_switch_position(int door, const Eigen::Vector3d& position) {
  return move_door_part(door, false, position);
}

}  // namespace macsim
