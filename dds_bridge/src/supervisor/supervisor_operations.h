// The supervisor's operations, one function each of the operation's name (set_density: the
// request's OP_SET_DENSITY), called (context, arguments), or (context) for an operation without
// arguments. The generated switch over the IDL's list of operations (idl/kurt/macsim_msgs.idl)
// calls them; a function missing here does not compile. Each fills the reply's results with
// fill() (the first reply field the IDL lists for it) and also() (each further one).
#pragma once

#include <cstdint>
#include <vector>

#include "macsim/msg/macsim_msgs.h"
#include "macsim/sim_core/snapshot_store.h"
#include "macsim/sim_core/world.h"

namespace macsim::ops {

namespace mm = macsim_msgs::msg::dds_;

/// What an operation runs against and the reply it fills.
struct Context {
  World& world;
  SnapshotStore& snapshots;
  mm::SupervisorReply_& reply;
};

/// The SupervisorReply_ field an operation lists first (`none`: none), or a further one.
namespace reply_field {
struct none {};
struct object_id {};
struct index {};
struct count {};
struct hash {};
struct object_ids {};
struct names {};
struct object {};
struct door {};
}  // namespace reply_field

inline PenetrationPolicy policy(bool allow_penetration) {
  return allow_penetration ? PenetrationPolicy::Allow : PenetrationPolicy::Refuse;
}

// What a World method's result puts in the reply.
Status fill(Context& c, const Status& status, reply_field::none);
Status fill(Context& c, const Result<ObjectId>& result, reply_field::object_id);
Status fill(Context& c, const Result<std::vector<ObjectId>>& result, reply_field::object_ids);
Status fill(Context& c, const std::vector<ObjectId>& ids, reply_field::object_ids);
Status fill(Context& c, int count, reply_field::count);
Status fill(Context& c, uint64_t hash, reply_field::hash);
/// An index: of a door when the reply also lists door (then also() below fills it).
Status fill(Context& c, const Result<int>& result, reply_field::index);
void also(Context& c, const std::vector<ObjectId>& ids, reply_field::count);
/// A door index's door and its parts' object ids (leaf, frame, platform, base; 0: none).
void also(Context& c, const Result<int>& door, reply_field::door);
void also(Context& c, const Result<int>& door, reply_field::object_ids);

// Operations that are one call of World or of one of its parts.
Status find_by_user_data(Context& c, const mm::UserData_& a);
Status destroy_object(Context& c, const mm::ObjectRef_& a);
Status set_pose(Context& c, const mm::SetPose_& a);
Status set_position(Context& c, const mm::SetPosition_& a);
Status set_orientation(Context& c, const mm::SetOrientation_& a);
Status set_box_size(Context& c, const mm::SetBoxSize_& a);
Status set_cylinder_size(Context& c, const mm::SetCylinderSize_& a);
Status set_sphere_size(Context& c, const mm::SetSphereSize_& a);
Status set_color(Context& c, const mm::SetColor_& a);
Status set_texture(Context& c, const mm::SetTexture_& a);
Status set_mass(Context& c, const mm::SetMass_& a);
Status set_density(Context& c, const mm::SetDensity_& a);
Status set_linear_velocity(Context& c, const mm::ObjectVector_& a);
Status set_angular_velocity(Context& c, const mm::ObjectVector_& a);
Status add_force(Context& c, const mm::ObjectVector_& a);
Status add_torque(Context& c, const mm::ObjectVector_& a);
Status set_frozen(Context& c, const mm::ObjectFlag_& a);
Status set_magnetizable(Context& c, const mm::ObjectFlag_& a);
Status set_user_data(Context& c, const mm::SetUserData_& a);
Status set_user_labels(Context& c, const mm::SetUserLabels_& a);
Status door_count(Context& c);
Status set_switch_triggered(Context& c, const mm::SetSwitchTriggered_& a);
Status set_door_position(Context& c, const mm::DoorPosition_& a);
Status set_switch_position(Context& c, const mm::DoorPosition_& a);
Status get_door_by_name(Context& c, const mm::DoorName_& a);
Status state_hash(Context& c);

// Operations whose arguments or results do not map onto one World method.
Status list_objects(Context& c);
Status find_object(Context& c, const mm::ObjectName_& a);
Status get_object(Context& c, const mm::ObjectRef_& a);
Status create_object(Context& c, const mm::CreateObject_& a);
Status import_environment(Context& c, const mm::ImportEnvironment_& a);
Status destroy_by_user_data(Context& c, const mm::UserData_& a);
Status destroy_all(Context& c, const mm::DestroyAll_& a);
Status set_ramp(Context& c, const mm::SetRamp_& a);
Status get_door(Context& c, const mm::DoorRef_& a);
Status reset(Context& c, const mm::Reset_& a);
Status save_snapshot(Context& c, const mm::SnapshotName_& a);
Status restore_snapshot(Context& c, const mm::SnapshotName_& a);
Status delete_snapshot(Context& c, const mm::SnapshotName_& a);
Status list_snapshots(Context& c);

}  // namespace macsim::ops
