#include "supervisor/supervisor_operations.h"

#include <string>

#include "supervisor/supervisor_codec.h"

namespace macsim::ops {

Status fill(Context&, const Status& status, reply_field::none) { return status; }

Status fill(Context& c, const Result<ObjectId>& result, reply_field::object_id) {
  if (result.ok()) c.reply.object_id(result.value);
  return result.status;
}

Status fill(Context& c, const Result<std::vector<ObjectId>>& result, reply_field::object_ids) {
  for (ObjectId each : result.value) c.reply.object_ids().push_back(each);
  return result.status;
}

Status fill(Context& c, const std::vector<ObjectId>& ids, reply_field::object_ids) {
  for (ObjectId each : ids) c.reply.object_ids().push_back(each);
  return Status{};
}

Status fill(Context& c, int count, reply_field::count) {
  c.reply.count(count);
  return Status{};
}

Status fill(Context& c, uint64_t hash, reply_field::hash) {
  c.reply.hash(hash);
  return Status{};
}

Status fill(Context& c, const Result<int>& result, reply_field::index) {
  if (result.ok()) c.reply.index(result.value);
  return result.status;
}

void also(Context& c, const std::vector<ObjectId>& ids, reply_field::count) {
  c.reply.count(static_cast<int32_t>(ids.size()));
}

void also(Context& c, const Result<int>& door, reply_field::door) {
  c.reply.door(codec::door_message(c.world, door.value));
}

void also(Context& c, const Result<int>& door, reply_field::object_ids) {
  auto parts = c.world.doors().door_parts(door.value);
  if (!parts.ok()) return;
  c.reply.object_ids({parts.value.leaf, parts.value.frame, parts.value.platform.value_or(0),
                      parts.value.base.value_or(0)});
}

Status list_objects(Context& c) {
  for (ObjectId each : c.world.objects().object_ids()) {
    c.reply.object_ids().push_back(each);
    c.reply.names().push_back(c.world.objects().object(each)->name);
  }
  c.reply.count(c.world.objects().object_count());
  return Status{};
}

Status find_object(Context& c, const mm::ObjectName_& a) {
  const auto found = c.world.objects().find_object(a.name());
  if (!found) return Status::error(ErrorCode::UnknownObject, "no object named '" + a.name() + "'");
  c.reply.object_id(*found);
  c.reply.index(*c.world.objects().index_of(*found));
  return Status{};
}

Status get_object(Context& c, const mm::ObjectRef_& a) {
  const ObjectId id = a.object_id();
  if (!c.world.objects().object(id)) {
    return Status::error(ErrorCode::UnknownObject, "no object with id " + std::to_string(id));
  }
  c.reply.object(codec::object_message(c.world, id));
  c.reply.object_id(id);
  c.reply.index(*c.world.objects().index_of(id));
  return Status{};
}

Status create_object(Context& c, const mm::CreateObject_& a) {
  std::string error;
  auto spec = codec::spec_of(a.object(), error);
  if (!spec) return Status::error(ErrorCode::InvalidArgument, error);
  return fill(c, c.world.edit().create_object(*spec, policy(a.allow_penetration())),
              reply_field::object_id{});
}

Status import_environment(Context& c, const mm::ImportEnvironment_& a) {
  Pose pose = codec::pose_of(a.pose());
  pose.orientation.normalize();
  return fill(c, c.world.edit().import_environment(a.file(), a.import_id(), pose),
              reply_field::object_ids{});
}

Status destroy_by_user_data(Context& c, const mm::UserData_& a) {
  return fill(c, c.world.edit().destroy_objects(a.user_data()), reply_field::count{});
}

Status destroy_all(Context& c, const mm::DestroyAll_& a) {
  switch (a.which()) {
    case mm::DESTROY_EVERY_OBJECT:
      return fill(c, c.world.edit().destroy_all_objects(), reply_field::count{});
    case mm::DESTROY_PORTABLE_OBJECTS:
      return fill(c, c.world.edit().destroy_all_portable_objects(), reply_field::count{});
    case mm::DESTROY_FIXED_OBJECTS:
      return fill(c, c.world.edit().destroy_all_fixed_objects(), reply_field::count{});
  }
  return Status::error(ErrorCode::InvalidArgument,
                       "which must be DESTROY_EVERY_OBJECT, DESTROY_PORTABLE_OBJECTS or "
                       "DESTROY_FIXED_OBJECTS; got " +
                           std::to_string(a.which()));
}

Status set_ramp(Context& c, const mm::SetRamp_& a) {
  return c.world.edit().set_ramp(a.object_id(), RampGeometry{a.width(), a.height(), a.angle()},
                                 policy(a.allow_penetration()));
}

Status get_door(Context& c, const mm::DoorRef_& a) {
  const int door = a.door();
  auto parts = c.world.doors().door_parts(door);
  if (!parts.ok()) return parts.status;
  const Result<int> found{Status{}, door};
  also(c, found, reply_field::door{});
  also(c, found, reply_field::object_ids{});
  return Status{};
}

Status reset(Context& c, const mm::Reset_& a) {
  const int scope = a.scope();
  if (scope != mm::RESET_POSES && scope != mm::RESET_POSES_AND_TIME &&
      scope != mm::RESET_EVERYTHING) {
    return Status::error(
        ErrorCode::InvalidArgument,
        "scope must be RESET_POSES, RESET_POSES_AND_TIME or RESET_EVERYTHING; got " +
            std::to_string(scope));
  }
  c.world.reset(static_cast<ResetScope>(scope));
  return Status{};
}

Status save_snapshot(Context& c, const mm::SnapshotName_& a) {
  return c.snapshots.save(a.name(), c.world.snapshot());
}

Status restore_snapshot(Context& c, const mm::SnapshotName_& a) {
  const WorldSnapshot* found = c.snapshots.find(a.name());
  if (!found) {
    return Status::error(ErrorCode::InvalidArgument,
                         "no snapshot named '" + a.name() + "' of this world");
  }
  return c.world.restore(*found);
}

Status delete_snapshot(Context& c, const mm::SnapshotName_& a) {
  return c.snapshots.remove(a.name());
}

Status list_snapshots(Context& c) {
  c.reply.names(c.snapshots.names());
  c.reply.count(static_cast<int32_t>(c.snapshots.size()));
  return Status{};
}

// ---- Operations that are one call of World or of one of its parts -------------------------

Status find_by_user_data(Context& c, const mm::UserData_& a) {
  const auto result = c.world.objects().find_by_user_data(a.user_data());
  Status status = fill(c, result, reply_field::object_ids{});
  if (status.ok()) also(c, result, reply_field::count{});
  return status;
}

Status destroy_object(Context& c, const mm::ObjectRef_& a) {
  return c.world.edit().destroy_object(a.object_id());
}

Status set_pose(Context& c, const mm::SetPose_& a) {
  return c.world.edit().set_pose(a.object_id(), codec::pose_of(a.pose()),
                                 policy(a.allow_penetration()));
}

Status set_position(Context& c, const mm::SetPosition_& a) {
  return c.world.edit().set_position(a.object_id(), codec::vector_of(a.position()),
                                     policy(a.allow_penetration()));
}

Status set_orientation(Context& c, const mm::SetOrientation_& a) {
  return c.world.edit().set_orientation(a.object_id(), codec::quaternion_of(a.orientation()),
                                        policy(a.allow_penetration()));
}

Status set_box_size(Context& c, const mm::SetBoxSize_& a) {
  return c.world.edit().set_box_size(a.object_id(), a.component_index(), codec::vector_of(a.size()),
                                     policy(a.allow_penetration()));
}

Status set_cylinder_size(Context& c, const mm::SetCylinderSize_& a) {
  return c.world.edit().set_cylinder_size(a.object_id(), a.component_index(), a.radius(),
                                          a.height(), policy(a.allow_penetration()));
}

Status set_sphere_size(Context& c, const mm::SetSphereSize_& a) {
  return c.world.edit().set_sphere_size(a.object_id(), a.component_index(), a.radius(),
                                        policy(a.allow_penetration()));
}

Status set_color(Context& c, const mm::SetColor_& a) {
  return c.world.edit().set_color(a.object_id(), a.rgba(), a.component_index());
}

Status set_texture(Context& c, const mm::SetTexture_& a) {
  return c.world.edit().set_texture(a.object_id(), a.file(), a.component_index());
}

Status set_mass(Context& c, const mm::SetMass_& a) {
  return c.world.edit().set_mass(a.object_id(), a.mass());
}

Status set_density(Context& c, const mm::SetDensity_& a) {
  return c.world.edit().set_density(a.object_id(), a.density());
}

Status set_linear_velocity(Context& c, const mm::ObjectVector_& a) {
  return c.world.edit().set_linear_velocity(a.object_id(), codec::vector_of(a.value()));
}

Status set_angular_velocity(Context& c, const mm::ObjectVector_& a) {
  return c.world.edit().set_angular_velocity(a.object_id(), codec::vector_of(a.value()));
}

Status add_force(Context& c, const mm::ObjectVector_& a) {
  return c.world.edit().add_force(a.object_id(), codec::vector_of(a.value()));
}

Status add_torque(Context& c, const mm::ObjectVector_& a) {
  return c.world.edit().add_torque(a.object_id(), codec::vector_of(a.value()));
}

Status set_frozen(Context& c, const mm::ObjectFlag_& a) {
  return c.world.edit().set_frozen(a.object_id(), a.value());
}

Status set_magnetizable(Context& c, const mm::ObjectFlag_& a) {
  return c.world.edit().set_magnetizable(a.object_id(), a.value());
}

Status set_user_data(Context& c, const mm::SetUserData_& a) {
  return c.world.edit().set_user_data(a.object_id(), a.user_data());
}

Status set_user_labels(Context& c, const mm::SetUserLabels_& a) {
  return c.world.edit().set_user_labels(a.object_id(), a.color_label(), a.shape_label());
}

Status door_count(Context& c) {
  return fill(c, c.world.doors().door_count(), reply_field::count{});
}

Status set_switch_triggered(Context& c, const mm::SetSwitchTriggered_& a) {
  return c.world.doors().set_switch_triggered(a.door(), a.triggered());
}

Status set_door_position(Context& c, const mm::DoorPosition_& a) {
  return c.world.doors().set_door_position(a.door(), codec::vector_of(a.position()));
}

Status set_switch_position(Context& c, const mm::DoorPosition_& a) {
  return c.world.doors().set_switch_position(a.door(), codec::vector_of(a.position()));
}

Status get_door_by_name(Context& c, const mm::DoorName_& a) {
  const auto result = c.world.doors().get_door_by_name(a.name());
  Status status = fill(c, result, reply_field::index{});
  if (status.ok()) also(c, result, reply_field::door{});
  if (status.ok()) also(c, result, reply_field::object_ids{});
  return status;
}

Status state_hash(Context& c) { return fill(c, c.world.state_hash(), reply_field::hash{}); }

}  // namespace macsim::ops
