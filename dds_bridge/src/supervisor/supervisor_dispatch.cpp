#include "supervisor/supervisor_dispatch.h"

#include <optional>

#include "macsim/dds/wire.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "supervisor/supervisor_codec.h"
#include "supervisor/supervisor_operations.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

namespace generated {

// The switch over the operations, each to its ops::<name> (idl/tools/generate_operations.py).
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

Command supervisor_command(const mm::SupervisorRequest_& q) {
  const int32_t op = q.operation()._d();
  Command c = request_command<SupervisorCall>(CommandSource::Supervisor, q, operation_name(op));
  if (op == mm::OP_RESET || op == mm::OP_RESTORE_SNAPSHOT)
    c.sent_before = codec::senders(q.commands_sent());
  return c;
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
