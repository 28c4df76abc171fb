// The hand-written part of the supervisor's dispatch. The generated part (from the IDL's list of
// operations, see idl/kurt/macsim_msgs.idl) runs each operation as a function of this namespace
// of the operation's name when one is declared here, called (context, arguments) or (context)
// for an operation without arguments; otherwise it calls the World method of the operation's
// name with the arguments' fields (in the order of the client's builder, converted: points and
// vectors to Eigen vectors, quaternions, poses, allow_penetration to a PenetrationPolicy) and
// hands its result to fill() with the first reply field the operation lists, then to also() for
// each further one.
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
