// A server's request as the runner queues it: the DDS sample itself, typed (gz-sim's typed user
// commands). It is encoded to CDR only when a session is written, and read back from a session's
// bytes only for a replay. `Kind` tells apart requests of one message type that run differently
// (a simulation request run, or answered as a repeat).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "macsim/dds/wire.h"
#include "macsim/sim_core/command.h"

namespace macsim {

template <class PubSubType, class Kind = void>
class TypedRequest final : public Request {
 public:
  using Message = typename PubSubType::type;
  /// `name`: the operation's, for logs and session files.
  TypedRequest(Message message, std::string name)
      : message_(std::move(message)), name_(std::move(name)) {}
  const Message& message() const { return message_; }
  std::string_view name() const override { return name_; }
  std::vector<uint8_t> wire() const override { return dds::to_wire<PubSubType>(message_); }
  /// The request a session recorded (its name and bytes), or nullptr when the bytes are none.
  static std::shared_ptr<const Request> read(const WireRequest& recorded) {
    auto message = dds::from_wire<PubSubType>(recorded.bytes);
    if (!message) return nullptr;
    return std::make_shared<const TypedRequest>(std::move(*message), recorded.operation);
  }

 private:
  Message message_;
  std::string name_;
};

}  // namespace macsim
