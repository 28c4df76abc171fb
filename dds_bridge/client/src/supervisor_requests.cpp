#include "macsim/client/supervisor_requests.h"

#include "macsim/dds/convert.h"

namespace macsim::client::supervisor {

namespace mm = macsim_msgs::msg::dds_;
namespace gm = geometry_msgs::msg::dds_;

namespace {

Request with(mm::SupervisorOperation_ operation) {
  Request r;
  r.operation(std::move(operation));
  return r;
}

gm::Point_ point(const Vec3& v) { return dds::point(v[0], v[1], v[2]); }
gm::Vector3_ vector(const Vec3& v) { return dds::vector3(v[0], v[1], v[2]); }
gm::Quaternion_ quaternion(const Quat& q) { return dds::quaternion(q[0], q[1], q[2], q[3]); }

Request no_arguments(int32_t operation) {
  mm::SupervisorOperation_ op;
  op.no_arguments(false);
  op._d(operation);
  return with(op);
}

Request object_ref(int32_t operation, uint32_t object_id) {
  mm::ObjectRef_ a;
  a.object_id(object_id);
  mm::SupervisorOperation_ op;
  op.object(a);
  op._d(operation);
  return with(op);
}

Request user_data_query(int32_t operation, const std::string& user_data) {
  mm::UserData_ a;
  a.user_data(user_data);
  mm::SupervisorOperation_ op;
  op.user_data(a);
  op._d(operation);
  return with(op);
}

Request object_vector(int32_t operation, uint32_t object_id, const Vec3& value) {
  mm::ObjectVector_ a;
  a.object_id(object_id);
  a.value(vector(value));
  mm::SupervisorOperation_ op;
  op.vector(a);
  op._d(operation);
  return with(op);
}

Request object_flag(int32_t operation, uint32_t object_id, bool value) {
  mm::ObjectFlag_ a;
  a.object_id(object_id);
  a.value(value);
  mm::SupervisorOperation_ op;
  op.flag(a);
  op._d(operation);
  return with(op);
}

Request door_position(int32_t operation, int32_t door, const Vec3& position) {
  mm::DoorPosition_ a;
  a.door(door);
  a.position(point(position));
  mm::SupervisorOperation_ op;
  op.door_position(a);
  op._d(operation);
  return with(op);
}

Request snapshot(int32_t operation, const std::string& name) {
  mm::SnapshotName_ a;
  a.name(name);
  mm::SupervisorOperation_ op;
  op.snapshot(a);
  op._d(operation);
  return with(op);
}

}  // namespace

Request list_objects() { return no_arguments(mm::OP_LIST_OBJECTS); }
Request door_count() { return no_arguments(mm::OP_DOOR_COUNT); }
Request state_hash() { return no_arguments(mm::OP_STATE_HASH); }

Request find_object(const std::string& name) {
  mm::ObjectName_ a;
  a.name(name);
  mm::SupervisorOperation_ op;
  op.find_object(a);
  return with(op);
}

Request find_by_user_data(const std::string& user_data) {
  return user_data_query(mm::OP_FIND_BY_USER_DATA, user_data);
}
Request destroy_by_user_data(const std::string& user_data) {
  return user_data_query(mm::OP_DESTROY_BY_USER_DATA, user_data);
}
Request get_object(uint32_t object_id) { return object_ref(mm::OP_GET_OBJECT, object_id); }
Request destroy_object(uint32_t object_id) { return object_ref(mm::OP_DESTROY_OBJECT, object_id); }

Request create_object(const mm::Object_& object, bool allow_penetration) {
  mm::CreateObject_ a;
  a.object(object);
  a.allow_penetration(allow_penetration);
  mm::SupervisorOperation_ op;
  op.create_object(a);
  return with(op);
}

Request import_environment(const std::string& file, const std::string& import_id,
                           const Vec3& position, const Quat& orientation) {
  mm::ImportEnvironment_ a;
  a.file(file);
  a.import_id(import_id);
  a.pose().position(point(position));
  a.pose().orientation(quaternion(orientation));
  mm::SupervisorOperation_ op;
  op.import_environment(a);
  return with(op);
}

Request destroy_all(int32_t which) {
  mm::DestroyAll_ a;
  a.which(which);
  mm::SupervisorOperation_ op;
  op.destroy_all(a);
  return with(op);
}

Request set_pose(uint32_t object_id, const Vec3& position, const Quat& orientation,
                 bool allow_penetration) {
  mm::SetPose_ a;
  a.object_id(object_id);
  a.pose().position(point(position));
  a.pose().orientation(quaternion(orientation));
  a.allow_penetration(allow_penetration);
  mm::SupervisorOperation_ op;
  op.set_pose(a);
  return with(op);
}

Request set_position(uint32_t object_id, const Vec3& position, bool allow_penetration) {
  mm::SetPosition_ a;
  a.object_id(object_id);
  a.position(point(position));
  a.allow_penetration(allow_penetration);
  mm::SupervisorOperation_ op;
  op.set_position(a);
  return with(op);
}

Request set_orientation(uint32_t object_id, const Quat& orientation, bool allow_penetration) {
  mm::SetOrientation_ a;
  a.object_id(object_id);
  a.orientation(quaternion(orientation));
  a.allow_penetration(allow_penetration);
  mm::SupervisorOperation_ op;
  op.set_orientation(a);
  return with(op);
}

Request set_box_size(uint32_t object_id, int32_t component, const Vec3& size,
                     bool allow_penetration) {
  mm::SetBoxSize_ a;
  a.object_id(object_id);
  a.component_index(component);
  a.size(vector(size));
  a.allow_penetration(allow_penetration);
  mm::SupervisorOperation_ op;
  op.set_box_size(a);
  return with(op);
}

Request set_cylinder_size(uint32_t object_id, int32_t component, double radius, double height,
                          bool allow_penetration) {
  mm::SetCylinderSize_ a;
  a.object_id(object_id);
  a.component_index(component);
  a.radius(radius);
  a.height(height);
  a.allow_penetration(allow_penetration);
  mm::SupervisorOperation_ op;
  op.set_cylinder_size(a);
  return with(op);
}

Request set_sphere_size(uint32_t object_id, int32_t component, double radius,
                        bool allow_penetration) {
  mm::SetSphereSize_ a;
  a.object_id(object_id);
  a.component_index(component);
  a.radius(radius);
  a.allow_penetration(allow_penetration);
  mm::SupervisorOperation_ op;
  op.set_sphere_size(a);
  return with(op);
}

Request set_ramp(uint32_t object_id, double width, double height, double angle,
                 bool allow_penetration) {
  mm::SetRamp_ a;
  a.object_id(object_id);
  a.width(width);
  a.height(height);
  a.angle(angle);
  a.allow_penetration(allow_penetration);
  mm::SupervisorOperation_ op;
  op.set_ramp(a);
  return with(op);
}

Request set_color(uint32_t object_id, const Rgba& rgba, int32_t component) {
  mm::SetColor_ a;
  a.object_id(object_id);
  a.component_index(component);
  a.rgba(rgba);
  mm::SupervisorOperation_ op;
  op.set_color(a);
  return with(op);
}

Request set_texture(uint32_t object_id, const std::string& file, int32_t component) {
  mm::SetTexture_ a;
  a.object_id(object_id);
  a.component_index(component);
  a.file(file);
  mm::SupervisorOperation_ op;
  op.set_texture(a);
  return with(op);
}

Request set_mass(uint32_t object_id, double mass) {
  mm::SetMass_ a;
  a.object_id(object_id);
  a.mass(mass);
  mm::SupervisorOperation_ op;
  op.set_mass(a);
  return with(op);
}

Request set_density(uint32_t object_id, double density) {
  mm::SetDensity_ a;
  a.object_id(object_id);
  a.density(density);
  mm::SupervisorOperation_ op;
  op.set_density(a);
  return with(op);
}

Request set_linear_velocity(uint32_t object_id, const Vec3& velocity) {
  return object_vector(mm::OP_SET_LINEAR_VELOCITY, object_id, velocity);
}
Request set_angular_velocity(uint32_t object_id, const Vec3& velocity) {
  return object_vector(mm::OP_SET_ANGULAR_VELOCITY, object_id, velocity);
}
Request add_force(uint32_t object_id, const Vec3& force) {
  return object_vector(mm::OP_ADD_FORCE, object_id, force);
}
Request add_torque(uint32_t object_id, const Vec3& torque) {
  return object_vector(mm::OP_ADD_TORQUE, object_id, torque);
}
Request set_frozen(uint32_t object_id, bool frozen) {
  return object_flag(mm::OP_SET_FROZEN, object_id, frozen);
}
Request set_magnetizable(uint32_t object_id, bool magnetizable) {
  return object_flag(mm::OP_SET_MAGNETIZABLE, object_id, magnetizable);
}

Request set_user_data(uint32_t object_id, const std::string& user_data) {
  mm::SetUserData_ a;
  a.object_id(object_id);
  a.user_data(user_data);
  mm::SupervisorOperation_ op;
  op.set_user_data(a);
  return with(op);
}

Request set_user_labels(uint32_t object_id, int32_t color_label, int32_t shape_label) {
  mm::SetUserLabels_ a;
  a.object_id(object_id);
  a.color_label(color_label);
  a.shape_label(shape_label);
  mm::SupervisorOperation_ op;
  op.set_user_labels(a);
  return with(op);
}

Request get_door(int32_t door) {
  mm::DoorRef_ a;
  a.door(door);
  mm::SupervisorOperation_ op;
  op.door(a);
  return with(op);
}

Request set_switch_triggered(int32_t door, bool triggered) {
  mm::SetSwitchTriggered_ a;
  a.door(door);
  a.triggered(triggered);
  mm::SupervisorOperation_ op;
  op.set_switch_triggered(a);
  return with(op);
}

Request set_door_position(int32_t door, const Vec3& position) {
  return door_position(mm::OP_SET_DOOR_POSITION, door, position);
}
Request set_switch_position(int32_t door, const Vec3& position) {
  return door_position(mm::OP_SET_SWITCH_POSITION, door, position);
}

Request reset(int32_t scope) {
  mm::Reset_ a;
  a.scope(scope);
  mm::SupervisorOperation_ op;
  op.reset(a);
  return with(op);
}

Request save_snapshot(const std::string& name) { return snapshot(mm::OP_SAVE_SNAPSHOT, name); }
Request restore_snapshot(const std::string& name) {
  return snapshot(mm::OP_RESTORE_SNAPSHOT, name);
}
Request delete_snapshot(const std::string& name) {
  return snapshot(mm::OP_DELETE_SNAPSHOT, name);
}
Request list_snapshots() { return no_arguments(mm::OP_LIST_SNAPSHOTS); }

}  // namespace macsim::client::supervisor
