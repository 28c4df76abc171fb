// The controller's (or experimenter's) handle on the simulator's supervisor over DDS.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"

namespace macsim::client {

/// Calls supervisor operations: each call sends a SupervisorRequest with this client's id and
/// the next sequence number, and waits for the reply that echoes both.
class SupervisorClient {
 public:
  using Request = macsim_msgs::msg::dds_::SupervisorRequest_;
  using Reply = macsim_msgs::msg::dds_::SupervisorReply_;

  /// `client_id` empty: one is made from the host's process id.
  explicit SupervisorClient(dds::Participant& participant, std::string client_id = "");

  /// Sends `request` (operation and arguments filled in) and waits for its reply; the request
  /// goes out again every second until answered (the server answers a repeat without redoing
  /// it). nullopt if no simulator answered within `timeout`.
  std::optional<Reply> call(Request request,
                            std::chrono::milliseconds timeout = std::chrono::seconds(10));
  /// A request for an operation on an object, with up to eight numbers.
  static Request request(int32_t operation, uint32_t object_id = 0,
                         std::initializer_list<double> values = {});
  /// Waits until a simulator's supervisor is matched both ways.
  bool wait_for_server(std::chrono::milliseconds timeout);
  const std::string& client_id() const { return client_id_; }

 private:
  std::string client_id_;
  uint64_t next_sequence_ = 1;
  std::mutex mutex_;
  std::condition_variable replied_;
  std::optional<Reply> reply_;
  uint64_t waiting_for_ = 0;
  dds::Writer<macsim_msgs::msg::dds_::SupervisorRequest_PubSubType> requests_;
  dds::Reader<macsim_msgs::msg::dds_::SupervisorReply_PubSubType> replies_;
};

}  // namespace macsim::client
