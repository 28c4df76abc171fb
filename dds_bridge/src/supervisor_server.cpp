#include "supervisor_server.h"

#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;
using dds::QosFamily;

namespace {

Eigen::Vector3d vec3(const std::array<double, 8>& v, int at = 0) { return {v[at], v[at + 1], v[at + 2]}; }

Eigen::Quaterniond quat(const std::array<double, 8>& v, int at) {
  return {v[at + 3], v[at], v[at + 1], v[at + 2]};  // x, y, z, w on the wire
}

geometry_msgs::msg::dds_::Pose_ pose_message(const Pose& p) {
  geometry_msgs::msg::dds_::Pose_ m;
  m.position(dds::point(p.position.x(), p.position.y(), p.position.z()));
  m.orientation(dds::quaternion(p.orientation.x(), p.orientation.y(), p.orientation.z(), p.orientation.w()));
  return m;
}

Pose pose_of(const geometry_msgs::msg::dds_::Pose_& m) {
  const auto& q = m.orientation();
  return {{m.position().x(), m.position().y(), m.position().z()}, Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z())};
}

mm::Object_ object_message(const World& world, ObjectId id) {
  mm::Object_ o;
  const ObjectSpec* spec = world.object(id);
  if (!spec) return o;
  const ObjectState state = world.object_state(id).value;
  o.id(id);
  o.name(spec->name);
  o.kind(static_cast<int32_t>(spec->kind));
  o.portable(spec->portable);
  for (const auto& c : spec->components) {
    mm::Component_ m;
    m.shape(static_cast<int32_t>(c.shape));
    m.size({c.size.x(), c.size.y(), c.size.z()});
    m.pose(pose_message(c.pose));
    m.color(c.color);
    m.texture(c.texture);
    o.components().push_back(m);
  }
  o.pose(pose_message(state.pose));
  o.velocity(dds::planar_twist(0, 0));
  o.velocity().linear(dds::vector3(state.linear_velocity.x(), state.linear_velocity.y(), state.linear_velocity.z()));
  o.velocity().angular(dds::vector3(state.angular_velocity.x(), state.angular_velocity.y(), state.angular_velocity.z()));
  o.density(spec->density);
  o.mass(spec->portable ? world.object_mass(id).value : 0.0);
  o.material(spec->material);
  o.magnetizable(spec->magnetizable);
  o.frozen(spec->frozen);
  o.user_data(spec->user_data);
  o.user_color(spec->user_color);
  o.user_shape(spec->user_shape);
  if (spec->ramp) o.ramp({spec->ramp->width, spec->ramp->height, spec->ramp->angle});
  return o;
}

ObjectSpec spec_of(const mm::Object_& o) {
  ObjectSpec spec;
  spec.name = o.name();
  spec.portable = o.portable();
  spec.pose = pose_of(o.pose());
  spec.density = o.density() > 0 ? o.density() : 100.0;
  if (!o.material().empty()) spec.material = o.material();
  spec.magnetizable = o.magnetizable();
  spec.frozen = o.frozen();
  spec.user_data = o.user_data();
  spec.user_color = o.user_color();
  spec.user_shape = o.user_shape();
  for (const auto& m : o.components()) {
    ComponentSpec c;
    c.shape = static_cast<Shape>(std::clamp(m.shape(), 0, 2));
    c.size = {m.size()[0], m.size()[1], m.size()[2]};
    c.pose = pose_of(m.pose());
    c.color = m.color();
    c.texture = m.texture();
    spec.components.push_back(c);
  }
  if (o.kind() == static_cast<int32_t>(ObjectKind::Ramp)) {
    spec.ramp = RampGeometry{o.ramp()[0], o.ramp()[1], o.ramp()[2]};
  }
  if (o.mass() > 0 && spec.volume() > 0) spec.density = o.mass() / spec.volume();
  return spec;
}

mm::Door_ door_message(const World& world, int door) {
  mm::Door_ d;
  const DoorState s = world.door_state(door).value;
  d.name(world.door_name(door));
  d.triggered(s.triggered);
  d.virtually_triggered(s.virtually_triggered);
  d.gap(static_cast<int32_t>(s.gap));
  d.opening(s.opening);
  d.switch_travel(s.switch_travel);
  return d;
}

const char* event_name(WorldEvent::Type type) {
  switch (type) {
    case WorldEvent::Type::SwitchTriggered: return "switch_triggered";
    case WorldEvent::Type::SwitchReleased: return "switch_released";
    case WorldEvent::Type::DoorOpened: return "door_opened";
    case WorldEvent::Type::DoorClosed: return "door_closed";
    case WorldEvent::Type::Penetration: return "penetration";
    case WorldEvent::Type::Instability: return "instability";
    case WorldEvent::Type::ObjectAttached: return "attached";
    case WorldEvent::Type::ObjectReleased: return "released";
  }
  return "?";
}

}  // namespace

SupervisorServer::SupervisorServer(dds::Participant& participant, Runner& runner)
    : runner_(runner),
      replies_(participant, dds::topics::kSupervisorReply, QosFamily::Command),
      objects_(participant, dds::topics::kWorldObjects, QosFamily::Latched),
      doors_(participant, dds::topics::kWorldDoors, QosFamily::Latched),
      events_(participant, dds::topics::kWorldEvents, QosFamily::Command) {
  // On Fast DDS's thread: copy the request and queue it; the world is touched only later.
  requests_ = std::make_unique<dds::Reader<mm::SupervisorRequest_PubSubType>>(
      participant, dds::topics::kSupervisorRequest, QosFamily::Command, [this](const Request& r) {
        runner_.push([this, r](World& world) { execute(r, world); });
      });
}

SupervisorServer::~SupervisorServer() { requests_.reset(); }

void SupervisorServer::execute(const Request& q, World& world) {
  // A client that did not hear its reply sends the same request again: answer, do not redo.
  if (auto last = last_reply_.find(q.client_id());
      last != last_reply_.end() && last->second.sequence_number() == q.sequence_number()) {
    replies_.write(last->second);
    return;
  }
  Reply reply;
  reply.client_id(q.client_id());
  reply.sequence_number(q.sequence_number());
  const auto& v = q.values();
  const ObjectId id = q.object_id();
  const auto policy = q.flag() ? PenetrationPolicy::Allow : PenetrationPolicy::Refuse;
  Status status;
  switch (q.operation()) {
    case mm::OP_LIST_OBJECTS:
      for (ObjectId each : world.object_ids()) {
        reply.object_ids().push_back(each);
        reply.names().push_back(world.object(each)->name);
      }
      reply.count(world.object_count());
      break;
    case mm::OP_FIND_OBJECT:
      if (auto found = world.find_object(q.name())) {
        reply.object_id(*found);
        reply.index(*world.index_of(*found));
      } else {
        status = Status::error(ErrorCode::UnknownObject, "no object named '" + q.name() + "'");
      }
      break;
    case mm::OP_FIND_BY_USER_DATA:
      for (ObjectId each : world.find_by_user_data(q.text())) reply.object_ids().push_back(each);
      reply.count(static_cast<int32_t>(reply.object_ids().size()));
      break;
    case mm::OP_GET_OBJECT:
      if (world.object(id)) {
        reply.object(object_message(world, id));
        reply.object_id(id);
        reply.index(*world.index_of(id));
      } else {
        status = Status::error(ErrorCode::UnknownObject, "no object with id " + std::to_string(id));
      }
      break;
    case mm::OP_CREATE_OBJECT: {
      auto created = world.create_object(spec_of(q.object()), policy);
      status = created.status;
      if (created.ok()) reply.object_id(created.value);
      break;
    }
    case mm::OP_IMPORT_ENVIRONMENT: {
      auto ids = world.import_environment(q.text(), q.name(), {vec3(v), quat(v, 3).normalized()});
      status = ids.status;
      for (ObjectId each : ids.value) reply.object_ids().push_back(each);
      break;
    }
    case mm::OP_DESTROY_OBJECT: status = world.destroy_object(id); break;
    case mm::OP_DESTROY_BY_USER_DATA: reply.count(world.destroy_objects(q.text())); break;
    case mm::OP_DESTROY_ALL:
      reply.count(q.index() == 1   ? world.destroy_all_portable_objects()
                  : q.index() == 2 ? world.destroy_all_fixed_objects()
                                   : world.destroy_all_objects());
      break;
    case mm::OP_SET_POSE: status = world.set_pose(id, {vec3(v), quat(v, 3)}, policy); break;
    case mm::OP_SET_POSITION: status = world.set_position(id, vec3(v), policy); break;
    case mm::OP_SET_ORIENTATION: status = world.set_orientation(id, quat(v, 0), policy); break;
    case mm::OP_SET_BOX_SIZE: status = world.set_box_size(id, q.index(), vec3(v), policy); break;
    case mm::OP_SET_CYLINDER_SIZE: status = world.set_cylinder_size(id, q.index(), v[0], v[1], policy); break;
    case mm::OP_SET_SPHERE_SIZE: status = world.set_sphere_size(id, q.index(), v[0], policy); break;
    case mm::OP_SET_RAMP: status = world.set_ramp(id, RampGeometry{v[0], v[1], v[2]}, policy); break;
    case mm::OP_SET_COLOR:
      status = world.set_color(id, {float(v[0]), float(v[1]), float(v[2]), float(v[3])}, q.index());
      break;
    case mm::OP_SET_TEXTURE: status = world.set_texture(id, q.text(), q.index()); break;
    case mm::OP_SET_MASS: status = world.set_mass(id, v[0]); break;
    case mm::OP_SET_DENSITY: status = world.set_density(id, v[0]); break;
    case mm::OP_SET_LINEAR_VELOCITY: status = world.set_linear_velocity(id, vec3(v)); break;
    case mm::OP_SET_ANGULAR_VELOCITY: status = world.set_angular_velocity(id, vec3(v)); break;
    case mm::OP_ADD_FORCE: status = world.add_force(id, vec3(v)); break;
    case mm::OP_ADD_TORQUE: status = world.add_torque(id, vec3(v)); break;
    case mm::OP_SET_FROZEN: status = world.set_frozen(id, q.flag()); break;
    case mm::OP_SET_MAGNETIZABLE: status = world.set_magnetizable(id, q.flag()); break;
    case mm::OP_SET_USER_DATA: status = world.set_user_data(id, q.text()); break;
    case mm::OP_SET_USER_LABELS:
      status = world.set_user_labels(id, static_cast<int>(v[0]), static_cast<int>(v[1]));
      break;
    case mm::OP_DOOR_COUNT: reply.count(world.door_count()); break;
    case mm::OP_GET_DOOR: {
      auto parts = world.door_parts(q.index());
      status = parts.status;
      if (parts.ok()) {
        reply.door(door_message(world, q.index()));
        reply.object_ids({parts.value.leaf, parts.value.frame, parts.value.platform.value_or(0),
                          parts.value.base.value_or(0)});
      }
      break;
    }
    case mm::OP_SET_SWITCH_TRIGGERED: status = world.set_switch_triggered(q.index(), q.flag()); break;
    case mm::OP_SET_DOOR_POSITION: status = world.set_door_position(q.index(), vec3(v)); break;
    case mm::OP_SET_SWITCH_POSITION: status = world.set_switch_position(q.index(), vec3(v)); break;
    case mm::OP_RESET:
      if (q.index() < 0 || q.index() > 2) {
        status = Status::error(ErrorCode::InvalidArgument, "reset scope must be 0, 1 or 2");
      } else {
        world.reset(static_cast<ResetScope>(q.index()));
      }
      break;
    case mm::OP_SAVE_SNAPSHOT: runner_.snapshots()[q.name()] = world.snapshot(); break;
    case mm::OP_RESTORE_SNAPSHOT:
      if (auto found = runner_.snapshots().find(q.name()); found != runner_.snapshots().end()) {
        status = world.restore(found->second);
      } else {
        status = Status::error(ErrorCode::InvalidArgument, "no snapshot named '" + q.name() + "'");
      }
      break;
    case mm::OP_STATE_HASH: reply.hash(world.state_hash()); break;
    default:
      status = Status::error(ErrorCode::InvalidArgument, "");
      reply.code(mm::ERR_UNKNOWN_OPERATION);
      reply.message("unknown operation " + std::to_string(q.operation()));
      break;
  }
  if (reply.code() != mm::ERR_UNKNOWN_OPERATION) {
    reply.code(static_cast<int32_t>(status.code));
    reply.message(status.message);
  }
  if (!status.penetrated.empty()) reply.names(status.penetrated);
  last_reply_[q.client_id()] = reply;
  replies_.write(reply);
}

void SupervisorServer::publish_world_state(World& world) {
  const double now = world.time();
  if (runner_.generation() != generation_) {
    // Ids belong to one world: every instance of the old world goes, whatever its id.
    for (uint32_t gone : published_ids_) {
      mm::ObjectState_ state;
      state.id(gone);
      objects_.dispose(state);
    }
    published_ids_.clear();
    generation_ = runner_.generation();
  }
  std::set<uint32_t> present;
  for (ObjectId id : world.object_ids()) {
    mm::ObjectState_ state;
    state.id(id);
    state.stamp(now);
    state.object(object_message(world, id));
    objects_.write(state);
    present.insert(id);
  }
  for (uint32_t gone : published_ids_) {
    if (present.count(gone)) continue;
    mm::ObjectState_ state;
    state.id(gone);
    objects_.dispose(state);  // the object was destroyed: its instance goes too
  }
  published_ids_ = std::move(present);
  for (int d = 0; d < world.door_count(); ++d) {
    mm::DoorState_ state;
    state.name(world.door_name(d));
    state.stamp(now);
    state.door(door_message(world, d));
    doors_.write(state);
  }
}

std::vector<std::string> SupervisorServer::topic_names() {
  return {dds::topics::kSupervisorRequest + " (macsim_msgs/SupervisorRequest, in)",
          dds::topics::kSupervisorReply + " (macsim_msgs/SupervisorReply, out)",
          dds::topics::kWorldObjects + " (macsim_msgs/ObjectState, keyed by object id, out)",
          dds::topics::kWorldDoors + " (macsim_msgs/DoorState, keyed by door name, out)",
          dds::topics::kWorldEvents + " (macsim_msgs/WorldEvent, out)"};
}

void SupervisorServer::publish() {
  World& world = runner_.world();
  for (const auto& e : world.take_events()) {
    mm::WorldEvent_ event;
    event.stamp(e.time);
    event.type(event_name(e.type));
    event.subject(e.subject);
    event.detail(e.detail);
    events_.write(event);
  }
  if (world.time() < last_time_ || runner_.generation() != generation_) {
    next_state_time_ = world.time();  // a reset or a new world: publish its state now
  }
  last_time_ = world.time();
  if (world.time() + 1e-9 >= next_state_time_) {
    next_state_time_ = world.time() + 0.1;
    publish_world_state(world);
  }
}

}  // namespace macsim
