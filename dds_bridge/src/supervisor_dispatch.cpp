#include "supervisor_dispatch.h"

#include <optional>

#include "supervisor_codec.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;
using codec::quaternion_of;
using codec::vector_of;

namespace {

PenetrationPolicy policy(bool allow_penetration) {
  return allow_penetration ? PenetrationPolicy::Allow : PenetrationPolicy::Refuse;
}

/// Runs the operation and fills the reply's results; nullopt for an unknown operation.
std::optional<Status> run(const mm::SupervisorOperation_& op, World& world,
                          SnapshotStore& snapshots, mm::SupervisorReply_& reply) {
  switch (op._d()) {
    case mm::OP_LIST_OBJECTS:
      for (ObjectId each : world.object_ids()) {
        reply.object_ids().push_back(each);
        reply.names().push_back(world.object(each)->name);
      }
      reply.count(world.object_count());
      return Status{};
    case mm::OP_FIND_OBJECT: {
      const auto found = world.find_object(op.find_object().name());
      if (!found) {
        return Status::error(ErrorCode::UnknownObject,
                             "no object named '" + op.find_object().name() + "'");
      }
      reply.object_id(*found);
      reply.index(*world.index_of(*found));
      return Status{};
    }
    case mm::OP_FIND_BY_USER_DATA:
      for (ObjectId each : world.find_by_user_data(op.user_data().user_data())) {
        reply.object_ids().push_back(each);
      }
      reply.count(static_cast<int32_t>(reply.object_ids().size()));
      return Status{};
    case mm::OP_GET_OBJECT: {
      const ObjectId id = op.object().object_id();
      if (!world.object(id)) {
        return Status::error(ErrorCode::UnknownObject, "no object with id " + std::to_string(id));
      }
      reply.object(codec::object_message(world, id));
      reply.object_id(id);
      reply.index(*world.index_of(id));
      return Status{};
    }
    case mm::OP_CREATE_OBJECT: {
      std::string error;
      auto spec = codec::spec_of(op.create_object().object(), error);
      if (!spec) return Status::error(ErrorCode::InvalidArgument, error);
      auto created = world.create_object(*spec, policy(op.create_object().allow_penetration()));
      if (created.ok()) reply.object_id(created.value);
      return created.status;
    }
    case mm::OP_IMPORT_ENVIRONMENT: {
      const auto& a = op.import_environment();
      Pose pose = codec::pose_of(a.pose());
      pose.orientation.normalize();
      auto ids = world.import_environment(a.file(), a.import_id(), pose);
      for (ObjectId each : ids.value) reply.object_ids().push_back(each);
      return ids.status;
    }
    case mm::OP_DESTROY_OBJECT:
      return world.destroy_object(op.object().object_id());
    case mm::OP_DESTROY_BY_USER_DATA:
      reply.count(world.destroy_objects(op.user_data().user_data()));
      return Status{};
    case mm::OP_DESTROY_ALL:
      switch (op.destroy_all().which()) {
        case mm::DESTROY_EVERY_OBJECT:
          reply.count(world.destroy_all_objects());
          return Status{};
        case mm::DESTROY_PORTABLE_OBJECTS:
          reply.count(world.destroy_all_portable_objects());
          return Status{};
        case mm::DESTROY_FIXED_OBJECTS:
          reply.count(world.destroy_all_fixed_objects());
          return Status{};
      }
      return Status::error(ErrorCode::InvalidArgument,
                           "which must be DESTROY_EVERY_OBJECT, DESTROY_PORTABLE_OBJECTS or "
                           "DESTROY_FIXED_OBJECTS; got " +
                               std::to_string(op.destroy_all().which()));
    case mm::OP_SET_POSE: {
      const auto& a = op.set_pose();
      return world.set_pose(a.object_id(), codec::pose_of(a.pose()), policy(a.allow_penetration()));
    }
    case mm::OP_SET_POSITION: {
      const auto& a = op.set_position();
      return world.set_position(a.object_id(), vector_of(a.position()),
                                policy(a.allow_penetration()));
    }
    case mm::OP_SET_ORIENTATION: {
      const auto& a = op.set_orientation();
      return world.set_orientation(a.object_id(), quaternion_of(a.orientation()),
                                   policy(a.allow_penetration()));
    }
    case mm::OP_SET_BOX_SIZE: {
      const auto& a = op.set_box_size();
      return world.set_box_size(a.object_id(), a.component_index(), vector_of(a.size()),
                                policy(a.allow_penetration()));
    }
    case mm::OP_SET_CYLINDER_SIZE: {
      const auto& a = op.set_cylinder_size();
      return world.set_cylinder_size(a.object_id(), a.component_index(), a.radius(), a.height(),
                                     policy(a.allow_penetration()));
    }
    case mm::OP_SET_SPHERE_SIZE: {
      const auto& a = op.set_sphere_size();
      return world.set_sphere_size(a.object_id(), a.component_index(), a.radius(),
                                   policy(a.allow_penetration()));
    }
    case mm::OP_SET_RAMP: {
      const auto& a = op.set_ramp();
      return world.set_ramp(a.object_id(), RampGeometry{a.width(), a.height(), a.angle()},
                            policy(a.allow_penetration()));
    }
    case mm::OP_SET_COLOR: {
      const auto& a = op.set_color();
      return world.set_color(a.object_id(), a.rgba(), a.component_index());
    }
    case mm::OP_SET_TEXTURE: {
      const auto& a = op.set_texture();
      return world.set_texture(a.object_id(), a.file(), a.component_index());
    }
    case mm::OP_SET_MASS:
      return world.set_mass(op.set_mass().object_id(), op.set_mass().mass());
    case mm::OP_SET_DENSITY:
      return world.set_density(op.set_density().object_id(), op.set_density().density());
    case mm::OP_SET_LINEAR_VELOCITY:
      return world.set_linear_velocity(op.vector().object_id(), vector_of(op.vector().value()));
    case mm::OP_SET_ANGULAR_VELOCITY:
      return world.set_angular_velocity(op.vector().object_id(), vector_of(op.vector().value()));
    case mm::OP_ADD_FORCE:
      return world.add_force(op.vector().object_id(), vector_of(op.vector().value()));
    case mm::OP_ADD_TORQUE:
      return world.add_torque(op.vector().object_id(), vector_of(op.vector().value()));
    case mm::OP_SET_FROZEN:
      return world.set_frozen(op.flag().object_id(), op.flag().value());
    case mm::OP_SET_MAGNETIZABLE:
      return world.set_magnetizable(op.flag().object_id(), op.flag().value());
    case mm::OP_SET_USER_DATA:
      return world.set_user_data(op.set_user_data().object_id(), op.set_user_data().user_data());
    case mm::OP_SET_USER_LABELS: {
      const auto& a = op.set_user_labels();
      return world.set_user_labels(a.object_id(), a.color_label(), a.shape_label());
    }
    case mm::OP_DOOR_COUNT:
      reply.count(world.door_count());
      return Status{};
    case mm::OP_GET_DOOR: {
      const int door = op.door().door();
      auto parts = world.door_parts(door);
      if (!parts.ok()) return parts.status;
      reply.door(codec::door_message(world, door));
      reply.object_ids({parts.value.leaf, parts.value.frame, parts.value.platform.value_or(0),
                        parts.value.base.value_or(0)});
      return Status{};
    }
    case mm::OP_SET_SWITCH_TRIGGERED:
      return world.set_switch_triggered(op.set_switch_triggered().door(),
                                        op.set_switch_triggered().triggered());
    case mm::OP_SET_DOOR_POSITION:
      return world.set_door_position(op.door_position().door(),
                                     vector_of(op.door_position().position()));
    case mm::OP_SET_SWITCH_POSITION:
      return world.set_switch_position(op.door_position().door(),
                                       vector_of(op.door_position().position()));
    case mm::OP_RESET: {
      const int scope = op.reset().scope();
      if (scope != mm::RESET_POSES && scope != mm::RESET_POSES_AND_TIME &&
          scope != mm::RESET_EVERYTHING) {
        return Status::error(
            ErrorCode::InvalidArgument,
            "scope must be RESET_POSES, RESET_POSES_AND_TIME or RESET_EVERYTHING; got " +
                std::to_string(scope));
      }
      world.reset(static_cast<ResetScope>(scope));
      return Status{};
    }
    case mm::OP_SAVE_SNAPSHOT:
      return snapshots.save(op.snapshot().name(), world.snapshot());
    case mm::OP_RESTORE_SNAPSHOT: {
      const WorldSnapshot* found = snapshots.find(op.snapshot().name());
      if (!found) {
        return Status::error(ErrorCode::InvalidArgument,
                             "no snapshot named '" + op.snapshot().name() + "' of this world");
      }
      return world.restore(*found);
    }
    case mm::OP_DELETE_SNAPSHOT:
      return snapshots.remove(op.snapshot().name());
    case mm::OP_LIST_SNAPSHOTS:
      reply.names(snapshots.names());
      reply.count(static_cast<int32_t>(snapshots.size()));
      return Status{};
    case mm::OP_STATE_HASH:
      reply.hash(world.state_hash());
      return Status{};
  }
  return std::nullopt;
}

}  // namespace

mm::SupervisorReply_ dispatch(const mm::SupervisorRequest_& request, World& world,
                              SnapshotStore& snapshots) {
  const auto addressed = [&request] {  // a reply to this request, nothing in it yet
    mm::SupervisorReply_ r;
    r.client_id(request.client_id());
    r.sequence_number(request.sequence_number());
    return r;
  };
  mm::SupervisorReply_ reply = addressed();
  std::optional<Status> ran;
  try {
    ran = run(request.operation(), world, snapshots, reply);
  } catch (const std::exception& e) {  // e.g. out of memory, or a check inside ODE
    reply = addressed();               // nothing half-filled goes out
    ran = Status::error(ErrorCode::InvalidArgument,
                        std::string("the request could not be carried out: ") + e.what());
  }
  if (!ran) {
    reply.code(mm::ERR_UNKNOWN_OPERATION);
    reply.message("unknown operation " + std::to_string(request.operation()._d()));
    return reply;
  }
  const Status& status = *ran;
  reply.code(codec::error_code(status.code));
  reply.message(status.message);
  if (!status.penetrated.empty()) reply.names(status.penetrated);
  return reply;
}

}  // namespace macsim
