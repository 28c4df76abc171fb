// World's parts (world.h): what objects(), edit() and doors() serve, each call handed to the
// World that holds the part (its implementation: world_supervisor.cpp).
#include "macsim/sim_core/world.h"

namespace macsim {

int WorldObjects::object_count() const {
  return world_.object_count();
}

std::optional<ObjectId> WorldObjects::object_at(int index) const {
  return world_.object_at(index);
}

std::optional<int> WorldObjects::index_of(ObjectId id) const {
  return world_.index_of(id);
}

std::optional<ObjectId> WorldObjects::find_object(const std::string& name) const {
  return world_.find_object(name);
}

std::vector<ObjectId> WorldObjects::find_by_user_data(const std::string& user_data) const {
  return world_.find_by_user_data(user_data);
}

std::vector<ObjectId> WorldObjects::object_ids() const {
  return world_.object_ids();
}

const ObjectSpec* WorldObjects::object(ObjectId id) const {
  return world_.object(id);
}

Result<ObjectState> WorldObjects::object_state(ObjectId id) const {
  return world_.object_state(id);
}

Result<double> WorldObjects::object_mass(ObjectId id) const {
  return world_.object_mass(id);
}

Result<Eigen::Matrix3d> WorldObjects::object_inertia(ObjectId id) const {
  return world_.object_inertia(id);
}

Result<Eigen::Vector3d> WorldObjects::object_center_of_mass(ObjectId id) const {
  return world_.object_center_of_mass(id);
}

Result<std::pair<Eigen::Vector3d, Eigen::Vector3d>> WorldObjects::object_wrench(ObjectId id) const {
  return world_.object_wrench(id);
}

Result<std::pair<int, std::string>> WorldObjects::object_texture(ObjectId id, int component) const {
  return world_.object_texture(id, component);
}

Status WorldObjects::free_body(ObjectId id, const std::string& what) const {
  return world_.free_body(id, what);
}

Result<ObjectId> WorldEditor::create_object(ObjectSpec spec, PenetrationPolicy policy) {
  return world_.create_object(std::move(spec), policy);
}

Result<std::vector<ObjectId>> WorldEditor::import_environment(const std::string& file, const std::string& id, const Pose& pose) {
  return world_.import_environment(file, id, pose);
}

Result<std::vector<ObjectId>> WorldEditor::add_environment(WorldSpec environment, const Pose& pose) {
  return world_.add_environment(std::move(environment), pose);
}

Status WorldEditor::destroy_object(ObjectId id) {
  return world_.destroy_object(id);
}

int WorldEditor::destroy_objects(const std::string& user_data) {
  return world_.destroy_objects(user_data);
}

int WorldEditor::destroy_all_objects() {
  return world_.destroy_all_objects();
}

int WorldEditor::destroy_all_portable_objects() {
  return world_.destroy_all_portable_objects();
}

int WorldEditor::destroy_all_fixed_objects() {
  return world_.destroy_all_fixed_objects();
}

Status WorldEditor::set_pose(ObjectId id, const Pose& pose, PenetrationPolicy policy) {
  return world_.set_pose(id, pose, policy);
}

Status WorldEditor::set_position(ObjectId id, const Eigen::Vector3d& position, PenetrationPolicy policy) {
  return world_.set_position(id, position, policy);
}

Status WorldEditor::set_orientation(ObjectId id, const Eigen::Quaterniond& orientation, PenetrationPolicy policy) {
  return world_.set_orientation(id, orientation, policy);
}

Status WorldEditor::set_box_size(ObjectId id, int component, const Eigen::Vector3d& size, PenetrationPolicy policy) {
  return world_.set_box_size(id, component, size, policy);
}

Status WorldEditor::set_cylinder_size(ObjectId id, int component, double radius, double height, PenetrationPolicy policy) {
  return world_.set_cylinder_size(id, component, radius, height, policy);
}

Status WorldEditor::set_sphere_size(ObjectId id, int component, double radius, PenetrationPolicy policy) {
  return world_.set_sphere_size(id, component, radius, policy);
}

Status WorldEditor::set_ramp(ObjectId id, const RampGeometry& ramp, PenetrationPolicy policy) {
  return world_.set_ramp(id, ramp, policy);
}

Status WorldEditor::set_color(ObjectId id, const Color& color, int component) {
  return world_.set_color(id, color, component);
}

Status WorldEditor::set_texture(ObjectId id, const std::string& path, int component) {
  return world_.set_texture(id, path, component);
}

Status WorldEditor::set_mass(ObjectId id, double mass) {
  return world_.set_mass(id, mass);
}

Status WorldEditor::set_density(ObjectId id, double density) {
  return world_.set_density(id, density);
}

Status WorldEditor::set_linear_velocity(ObjectId id, const Eigen::Vector3d& velocity) {
  return world_.set_linear_velocity(id, velocity);
}

Status WorldEditor::set_angular_velocity(ObjectId id, const Eigen::Vector3d& velocity) {
  return world_.set_angular_velocity(id, velocity);
}

Status WorldEditor::add_force(ObjectId id, const Eigen::Vector3d& force) {
  return world_.add_force(id, force);
}

Status WorldEditor::add_torque(ObjectId id, const Eigen::Vector3d& torque) {
  return world_.add_torque(id, torque);
}

Status WorldEditor::set_frozen(ObjectId id, bool frozen) {
  return world_.set_frozen(id, frozen);
}

Status WorldEditor::set_magnetizable(ObjectId id, bool magnetizable) {
  return world_.set_magnetizable(id, magnetizable);
}

Status WorldEditor::set_user_data(ObjectId id, const std::string& user_data) {
  return world_.set_user_data(id, user_data);
}

Status WorldEditor::set_user_labels(ObjectId id, int user_color, int user_shape) {
  return world_.set_user_labels(id, user_color, user_shape);
}

int WorldDoors::door_count() const {
  return world_.door_count();
}

std::optional<int> WorldDoors::find_door(const std::string& name) const {
  return world_.find_door(name);
}

Result<int> WorldDoors::get_door_by_name(const std::string& name) const {
  return world_.get_door_by_name(name);
}

Result<DoorState> WorldDoors::door_state(int door) const {
  return world_.door_state(door);
}

Result<DoorParts> WorldDoors::door_parts(int door) const {
  return world_.door_parts(door);
}

const std::string& WorldDoors::door_name(int door) const {
  return world_.door_name(door);
}

Status WorldDoors::set_switch_triggered(int door, bool triggered) {
  return world_.set_switch_triggered(door, triggered);
}

Status WorldDoors::set_door_position(int door, const Eigen::Vector3d& position) {
  return world_.set_door_position(door, position);
}

Status WorldDoors::set_switch_position(int door, const Eigen::Vector3d& position) {
  return world_.set_switch_position(door, position);
}

}  // namespace macsim
