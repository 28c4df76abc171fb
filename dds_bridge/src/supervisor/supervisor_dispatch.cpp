#include "supervisor/supervisor_dispatch.h"

#include <optional>

#include "macsim/dds/wire.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "supervisor/supervisor_codec.h"
#include "supervisor/supervisor_operations.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

namespace generated {

using ops::policy;
namespace reply_field = ops::reply_field;

// One function per operation and the switch over them (idl/tools/generate_operations.py).
#include "supervisor_dispatch_operations.inc"

}  // namespace generated

namespace {

/// Runs the operation and fills the reply's results; nullopt for an unknown operation.
std::optional<Status> run(const mm::SupervisorOperation_& op, World& world,
                          SnapshotStore& snapshots, mm::SupervisorReply_& reply) {
  ops::Context context{world, snapshots, reply};
  return generated::run_operation(context, op);
}

}  // namespace

bool changes_world(int32_t code) { return generated::changes_world(code); }

bool replay(const Command& command, World& world, SnapshotStore& snapshots) {
  const auto request = dds::from_wire<mm::SupervisorRequest_PubSubType>(command.message);
  if (request) dispatch(*request, world, snapshots);
  return request.has_value();
}

std::string operation_name(int32_t code) {
  const char* name = generated::name_of(code);
  return name ? name : "operation_" + std::to_string(code);
}

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
