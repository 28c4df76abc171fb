// WorldEditor (world.h): the supervisor's changes to the world's objects: created, imported,
// destroyed, moved, resized, re-coloured, pushed. Every operation checks its arguments before
// touching ODE: on error the world is unchanged.
#include <algorithm>
#include <cmath>

#include "macsim/sim_core/data_roots.h"
#include "macsim/sim_core/texture.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_bounds.h"
#include "macsim/sim_core/world_loader.h"
#include "world_internal.h"

namespace macsim {

namespace {

/// Why a pose is unusable (out of bounds, not finite, a zero quaternion), or nothing.
std::optional<std::string> pose_problem(const Pose& p) {
  if (auto problem = bounds::position_problem(p.position)) return problem;
  return bounds::orientation_problem(p.orientation);
}

/// LimitReached: `adding` more objects would pass the world's cap.
Status objects_capped(std::size_t count, std::size_t adding, std::size_t cap) {
  return Status::error(ErrorCode::LimitReached,
                       "the world holds " + std::to_string(count) + " objects and may hold " +
                           std::to_string(cap) + " (macsim --max-objects); " +
                           std::to_string(adding) +
                           " more would pass the cap: destroy some first, or raise the cap");
}

}  // namespace

Status WorldEditor::validate_new_object(ObjectSpec& spec) const {
  if (table_.size() >= max_objects_) return objects_capped(table_.size(), 1, max_objects_);
  if (spec.kind != ObjectKind::Object && spec.kind != ObjectKind::Wall &&
      spec.kind != ObjectKind::Ramp) {
    return detail::invalid_argument(
        "door and switch parts are created with import_environment(), not alone");
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
    return detail::invalid_argument("a ramp needs its ramp geometry (width, height, angle)");
  }
  if (auto p = bounds::object_problem(spec)) return detail::invalid_argument(*p);
  normalize_orientations(spec);
  for (auto& c : spec.components) {
    if (!c.texture.empty()) {
      if (Status s = texture_status(c.texture); !s.ok()) return s;
      c.texture = physics_.data_roots().identity(c.texture);  // the file checked, in one spelling
    }
  }
  if (!physics_.material(spec.material))
    return detail::invalid_argument("unknown material '" + spec.material + "'");
  if (!spec.name.empty()) {
    if (auto p = bounds::name_problem(spec.name)) return detail::invalid_argument(*p);
  }
  if (!spec.name.empty() && table_.find_named(spec.name)) {
    return detail::invalid_argument("an object named '" + spec.name + "' exists already");
  }
  return {};
}

Result<ObjectId> WorldEditor::create_object(ObjectSpec spec, PenetrationPolicy policy) {
  if (Status s = validate_new_object(spec); !s.ok()) return {s};
  const ObjectId id = table_.take_id();
  if (spec.name.empty()) spec.name = "object_" + std::to_string(id);
  detail::ObjectRecord& o = table_.add(id, std::move(spec));
  physics_.build_object(o);
  Status status;
  status.penetrated = physics_.penetrations(o);
  if (!status.penetrated.empty()) {
    if (policy == PenetrationPolicy::Refuse) {
      Status refused =
          Status::error(ErrorCode::Penetration,
                        "'" + o.spec.name + "' would penetrate " + status.penetrated.front());
      physics_.destroy_object(o);
      table_.erase(id);        // `o` is gone from here on
      table_.set_next_id(id);  // the world as it was, its next id included
      return {refused};
    }
    physics_.emit(WorldEvent::Type::Penetration, o.spec.name,
                  "created inside " + status.penetrated.front());
  }
  physics_.structure_changed();
  return {status, o.id};
}

Status WorldEditor::add_spec_objects(WorldSpec fragment, std::vector<ObjectId>* ids) {
  if (!fragment.robots.empty())
    return detail::invalid_argument("robots cannot be added to a running world");
  if (table_.size() + fragment.objects.size() > max_objects_) {
    return objects_capped(table_.size(), fragment.objects.size(), max_objects_);
  }
  for (const auto& object : fragment.objects) {
    if (table_.find_named(object.name))
      return detail::invalid_argument("an object named '" + object.name + "' exists already");
  }
  for (const auto& m : fragment.materials) {
    if (!physics_.material(m.name)) physics_.materials().push_back(m);
  }
  std::vector<detail::ObjectRecord*> added;
  for (auto& object : fragment.objects)
    added.push_back(&table_.add(table_.take_id(), std::move(object)));
  std::vector<detail::JointRecord*> new_joints;
  for (auto& joint : fragment.joints) new_joints.push_back(&table_.add_joint(std::move(joint)));
  for (auto& door : fragment.doors) doors_.add(std::move(door), {});
  doors_.wire();
  for (detail::ObjectRecord* o : added) {
    physics_.build_object(*o);
    if (ids) ids->push_back(o->id);
  }
  for (detail::JointRecord* j : new_joints) physics_.build_joint(*j);
  physics_.structure_changed();
  return {};
}

Result<std::vector<ObjectId>> WorldEditor::import_environment(const std::string& file,
                                                              const std::string& id,
                                                              const Pose& pose) {
  if (auto p = pose_problem(pose)) return {detail::invalid_argument("the import's " + *p)};
  if (auto p = bounds::id_problem(id)) return {detail::invalid_argument("import id: " + *p)};
  WorldSpec fragment;
  try {
    fragment = load_environment_file(file, id, physics_.materials(), physics_.data_roots());
  } catch (const WorldFileError& e) {
    return {Status::error(ErrorCode::BadFile, e.what())};
  } catch (const FileRefused& e) {  // outside the data roots, a special file, too large
    return {Status::error(ErrorCode::BadFile, e.what())};
  } catch (const std::exception& e) {  // e.g. a path the file system refuses
    return {Status::error(ErrorCode::BadFile, "cannot import '" + file + "': " + e.what())};
  }
  return add_environment(std::move(fragment), pose);
}

Result<std::vector<ObjectId>> WorldEditor::add_environment(WorldSpec fragment, const Pose& pose) {
  if (auto p = pose_problem(pose)) return {detail::invalid_argument("the environment's " + *p)};
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
    return {detail::invalid_argument(e.what())};
  }
  std::vector<ObjectId> ids;
  if (Status s = add_spec_objects(std::move(fragment), &ids); !s.ok()) return {s};
  return {{}, ids};
}

void WorldEditor::erase_object(ObjectId id) {
  detail::ObjectRecord* o = table_.find(id);
  if (!o) return;
  std::vector<const detail::JointRecord*> holding;
  for (const auto& j : table_.joints()) {
    if (j->spec.body1 == o->spec.name || j->spec.body2 == o->spec.name) holding.push_back(j.get());
  }
  for (const detail::JointRecord* j : holding) {
    if (j->joint) dJointDestroy(j->joint);
    table_.erase_joint(j);
  }
  physics_.destroy_object(*o);
  table_.erase(id);
}

Status WorldEditor::destroy_object(ObjectId id) {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
  if (o->door >= 0) {
    // A door part takes its whole door-switch structure with it.
    const int door = o->door;
    const DoorParts parts = doors_.parts(door);
    for (const auto part : {std::optional<ObjectId>(parts.leaf),
                            std::optional<ObjectId>(parts.frame), parts.platform, parts.base}) {
      if (part) erase_object(*part);
    }
    doors_.remove(door);
    for (const auto& other :
         table_.objects()) {  // later doors' indices moved down: their groups too
      if (other->door >= door) other->tag.group = 1'000'000 + other->door;
    }
  } else {
    erase_object(id);
  }
  physics_.structure_changed();
  return {};
}

int WorldEditor::destroy_matching(const std::function<bool(const ObjectSpec&)>& match) {
  int destroyed = 0;
  for (bool again = true; again;) {
    again = false;
    for (const auto& o : table_.objects()) {
      if (match(o->spec)) {
        const std::size_t before = table_.size();
        destroy_object(o->id);
        destroyed += static_cast<int>(before - table_.size());
        again = true;
        break;
      }
    }
  }
  return destroyed;
}

int WorldEditor::destroy_objects(const std::string& user_data) {
  return destroy_matching([&](const ObjectSpec& s) { return s.user_data == user_data; });
}

int WorldEditor::destroy_all_objects() {
  return destroy_matching([](const ObjectSpec&) { return true; });
}

int WorldEditor::destroy_all_portable_objects() {
  return destroy_matching([](const ObjectSpec& s) { return s.portable; });
}

int WorldEditor::destroy_all_fixed_objects() {
  return destroy_matching([](const ObjectSpec& s) { return !s.portable; });
}

void WorldEditor::rebuild_object(detail::ObjectRecord& o, const ObjectSpec& spec,
                                 const ObjectState& state) {
  std::vector<detail::JointRecord*> attached;
  for (const auto& j : table_.joints()) {
    if (j->joint && (j->spec.body1 == o.spec.name || j->spec.body2 == o.spec.name)) {
      j->position = j->spec.type == JointSpec::Type::Slider ? dJointGetSliderPosition(j->joint)
                                                            : dJointGetHingeAngle(j->joint);
      dJointDestroy(j->joint);
      j->joint = nullptr;
      attached.push_back(j.get());
    }
  }
  physics_.destroy_object(o, true);  // changed in place: it keeps its place in ODE's order
  o.spec = spec;
  if (attached.empty()) {
    o.spec.pose = state.pose;  // a jointed body keeps its joint's zero as its reference pose
  }
  physics_.build_object(o);
  if (o.body) {
    const Pose body = state.pose * Pose{o.com, Eigen::Quaterniond::Identity()};
    detail::set_body_state(
        o.body, {body.position, body.orientation, state.linear_velocity, state.angular_velocity});
  }
  for (detail::JointRecord* j : attached) physics_.build_joint(*j);
}

Status WorldEditor::change_object(ObjectId id, PenetrationPolicy policy,
                                  const std::function<Status(ObjectSpec&, Pose&)>& change) {
  const detail::ObjectRecord* found = nullptr;
  if (Status s = table_.check(id, found); !s.ok()) return s;
  detail::ObjectRecord& o = *table_.find(id);
  const ObjectSpec old_spec = o.spec;
  const ObjectState old_state = detail::object_state(o);
  ObjectSpec spec = o.spec;
  Pose pose = old_state.pose;
  if (Status s = change(spec, pose); !s.ok()) return s;
  ObjectSpec placed = spec;  // the changed object where it will stand: within bounds?
  placed.pose = pose;
  if (auto p = bounds::object_problem(placed)) return detail::invalid_argument(*p);
  ObjectState state = old_state;
  state.pose = pose;
  rebuild_object(o, spec, state);
  Status status;
  status.penetrated = physics_.penetrations(o);
  if (!status.penetrated.empty()) {
    if (policy == PenetrationPolicy::Refuse) {
      rebuild_object(o, old_spec, old_state);
      physics_.structure_changed();
      Status refused =
          Status::error(ErrorCode::Penetration, "refused: '" + o.spec.name + "' would penetrate '" +
                                                    status.penetrated.front() + "'");
      refused.penetrated = status.penetrated;
      return refused;
    }
    physics_.emit(WorldEvent::Type::Penetration, o.spec.name,
                  "penetrates " + status.penetrated.front());
  }
  physics_.structure_changed();
  return status;
}

Status WorldEditor::set_pose(ObjectId id, const Pose& pose, PenetrationPolicy policy) {
  if (auto p = pose_problem(pose)) return detail::invalid_argument(*p);
  const detail::ObjectRecord* o = table_.find(id);
  if (o && o->door >= 0) {
    return Status::error(ErrorCode::NotApplicable,
                         "'" + o->spec.name + "' is part of door '" +
                             doors_.doors().at(o->door)->spec.name +
                             "': move it with set_door_position or set_switch_position");
  }
  Pose target = pose;
  target.orientation.normalize();
  return change_object(id, policy, [&](ObjectSpec&, Pose& p) {
    p = target;
    return Status{};
  });
}

Status WorldEditor::set_position(ObjectId id, const Eigen::Vector3d& position,
                                 PenetrationPolicy policy) {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
  Pose pose = detail::object_state(*o).pose;
  pose.position = position;
  return set_pose(id, pose, policy);
}

Status WorldEditor::set_orientation(ObjectId id, const Eigen::Quaterniond& orientation,
                                    PenetrationPolicy policy) {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
  Pose pose = detail::object_state(*o).pose;
  pose.orientation = orientation;
  return set_pose(id, pose, policy);
}

Status WorldEditor::resize_component(ObjectId id, int component, Shape shape,
                                     const Eigen::Vector3d& size, PenetrationPolicy policy) {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
  if (o->spec.kind == ObjectKind::Ramp) {
    return Status::error(ErrorCode::WrongGeometry,
                         "'" + o->spec.name + "' is a ramp: change it with set_ramp");
  }
  if (component < 0 || component >= static_cast<int>(o->spec.components.size())) {
    return detail::invalid_argument("'" + o->spec.name + "' has no component " +
                                    std::to_string(component) + " (it has " +
                                    std::to_string(o->spec.components.size()) + ")");
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

Status WorldEditor::set_box_size(ObjectId id, int component, const Eigen::Vector3d& size,
                                 PenetrationPolicy policy) {
  return resize_component(id, component, Shape::Box, size, policy);
}

Status WorldEditor::set_cylinder_size(ObjectId id, int component, double radius, double height,
                                      PenetrationPolicy policy) {
  return resize_component(id, component, Shape::Cylinder, {radius, 0.0, height}, policy);
}

Status WorldEditor::set_sphere_size(ObjectId id, int component, double radius,
                                    PenetrationPolicy policy) {
  return resize_component(id, component, Shape::Sphere, {radius, 0.0, 0.0}, policy);
}

Status WorldEditor::set_ramp(ObjectId id, const RampGeometry& ramp, PenetrationPolicy policy) {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
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

Status WorldEditor::set_color(ObjectId id, const Color& color, int component) {
  const detail::ObjectRecord* found = nullptr;
  if (Status s = table_.check(id, found); !s.ok()) return s;
  for (float channel : color) {
    if (!std::isfinite(channel) || channel < 0 || channel > 1)
      return detail::invalid_argument("colour channels must lie in [0, 1]");
  }
  detail::ObjectRecord& o = *table_.find(id);
  if (component < -1 || component >= static_cast<int>(o.spec.components.size())) {
    return detail::invalid_argument("'" + o.spec.name + "' has no component " +
                                    std::to_string(component));
  }
  for (int i = 0; i < static_cast<int>(o.spec.components.size()); ++i) {
    if (component == -1 || component == i) o.spec.components[i].color = color;
  }
  return {};
}

Status WorldEditor::texture_status(const std::string& path) const {
  try {
    if (auto p = texture_problem(path, physics_.data_roots()))
      return Status::error(ErrorCode::BadTexture, *p);
  } catch (const FileRefused& refused) {
    return Status::error(ErrorCode::BadFile, refused.what());
  }
  return {};
}

Status WorldEditor::set_texture(ObjectId id, const std::string& path, int component) {
  const detail::ObjectRecord* found = nullptr;
  if (Status s = table_.check(id, found); !s.ok()) return s;
  detail::ObjectRecord& o = *table_.find(id);
  if (component < -1 || component >= static_cast<int>(o.spec.components.size())) {
    return detail::invalid_argument("'" + o.spec.name + "' has no component " +
                                    std::to_string(component));
  }
  std::string file;
  if (!path.empty()) {
    if (Status s = texture_status(path); !s.ok()) return s;
    file = physics_.data_roots().identity(path);  // the file checked, in one spelling
  }
  for (int i = 0; i < static_cast<int>(o.spec.components.size()); ++i) {
    if (component == -1 || component == i) o.spec.components[i].texture = file;
  }
  return {};
}

Status WorldEditor::set_mass(ObjectId id, double mass) {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
  if (!std::isfinite(mass) || mass <= 0)
    return detail::invalid_argument("mass must be finite and positive");
  if (!o->spec.portable) {
    return Status::error(ErrorCode::NotApplicable,
                         "'" + o->spec.name + "' is fixed: it has no mass");
  }
  return change_object(id, PenetrationPolicy::Allow, [&](ObjectSpec& spec, Pose&) {
    spec.density = mass / spec.volume();
    return Status{};
  });
}

Status WorldEditor::set_density(ObjectId id, double density) {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
  if (!std::isfinite(density) || density <= 0)
    return detail::invalid_argument("density must be finite and positive");
  if (!o->spec.portable) {
    return Status::error(ErrorCode::NotApplicable,
                         "'" + o->spec.name + "' is fixed: it has no density");
  }
  return change_object(id, PenetrationPolicy::Allow, [&](ObjectSpec& spec, Pose&) {
    spec.density = density;
    return Status{};
  });
}

Status WorldEditor::dynamic_body(ObjectId id, const Eigen::Vector3d& value, const char* what,
                                 dxBody*& body) const {
  const detail::ObjectRecord* o = nullptr;
  if (Status s = table_.check(id, o); !s.ok()) return s;
  const bool angular = std::string(what) == "angular velocity";
  const double max = std::string(what) == "linear velocity" ? bounds::kMaxSpeed
                     : angular                              ? bounds::kMaxAngularSpeed
                                                            : bounds::kMaxForce;
  if (auto p = bounds::magnitude_problem(value, max, what)) return detail::invalid_argument(*p);
  if (Status s = detail::free_body(*o, what); !s.ok()) return s;
  body = o->body;
  physics_.wake(body);  // it is about to move
  return {};
}

Status WorldEditor::set_linear_velocity(ObjectId id, const Eigen::Vector3d& v) {
  dBodyID body = nullptr;
  if (Status s = dynamic_body(id, v, "linear velocity", body); !s.ok()) return s;
  dBodySetLinearVel(body, v.x(), v.y(), v.z());
  return {};
}

Status WorldEditor::set_angular_velocity(ObjectId id, const Eigen::Vector3d& w) {
  dBodyID body = nullptr;
  if (Status s = dynamic_body(id, w, "angular velocity", body); !s.ok()) return s;
  dBodySetAngularVel(body, w.x(), w.y(), w.z());
  return {};
}

Status WorldEditor::add_force(ObjectId id, const Eigen::Vector3d& f) {
  dBodyID body = nullptr;
  if (Status s = dynamic_body(id, f, "force", body); !s.ok()) return s;
  dBodyAddForce(body, f.x(), f.y(), f.z());
  return {};
}

Status WorldEditor::add_torque(ObjectId id, const Eigen::Vector3d& t) {
  dBodyID body = nullptr;
  if (Status s = dynamic_body(id, t, "torque", body); !s.ok()) return s;
  dBodyAddTorque(body, t.x(), t.y(), t.z());
  return {};
}

Status WorldEditor::set_frozen(ObjectId id, bool frozen) {
  const detail::ObjectRecord* found = nullptr;
  if (Status s = table_.check(id, found); !s.ok()) return s;
  detail::ObjectRecord& o = *table_.find(id);
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
    physics_.wake(o.body);
  }
  return {};
}

Status WorldEditor::set_magnetizable(ObjectId id, bool magnetizable) {
  const detail::ObjectRecord* found = nullptr;
  if (Status s = table_.check(id, found); !s.ok()) return s;
  table_.find(id)->spec.magnetizable = magnetizable;
  return {};
}

Status WorldEditor::set_user_data(ObjectId id, const std::string& user_data) {
  const detail::ObjectRecord* found = nullptr;
  if (Status s = table_.check(id, found); !s.ok()) return s;
  table_.find(id)->spec.user_data = user_data;
  return {};
}

Status WorldEditor::set_user_labels(ObjectId id, int user_color, int user_shape) {
  const detail::ObjectRecord* found = nullptr;
  if (Status s = table_.check(id, found); !s.ok()) return s;
  table_.find(id)->spec.user_color = user_color;
  table_.find(id)->spec.user_shape = user_shape;
  return {};
}

}  // namespace macsim
