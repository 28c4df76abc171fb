// One of macsim's own services (correlated in the payload: replies echo the client id and
// sequence number) on the request/reply transport the ROS 2 services use too
// (dds::ServiceServer): a reply also names its request's sample identity when it is known.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <shared_mutex>

#include "macsim/dds/ros2_service.h"

namespace macsim {

/// Requests in on Fast DDS's thread, replies out from any thread, until close().
template <class RequestType, class ReplyType>
class RequestService {
 public:
  using Request = typename RequestType::type;
  using Reply = typename ReplyType::type;
  using Server = dds::ServiceServer<RequestType, ReplyType>;

  /// Serves the topics: `on_request` hears each request (copy or enqueue it, nothing more).
  void open(dds::Participant& participant, const dds::ServiceTopics& topics,
            typename Server::Handler on_request) {
    auto server = std::make_unique<Server>(participant, topics, std::move(on_request));
    std::unique_lock<std::shared_mutex> lock(mutex_);
    server_ = std::move(server);
  }
  /// No request comes in and no reply goes out any more.
  void close() {
    std::unique_ptr<Server> gone;
    {
      std::unique_lock<std::shared_mutex> lock(mutex_);
      gone = std::move(server_);
    }
    gone.reset();  // outside the lock: a request being heard may still reply (to no one)
  }
  /// Sends a reply; with `id`, it names that request's sample identity too. Replies from
  /// several threads go out side by side; only close() waits for them.
  void reply(const Reply& reply, const dds::RequestId* id = nullptr) {
    std::shared_lock<std::shared_mutex> lock(mutex_);
    if (!server_) return;
    if (id) {
      server_->reply(*id, reply);
    } else {
      server_->publish(reply);
    }
  }

 private:
  std::shared_mutex mutex_;  // exclusive only to open and close
  std::unique_ptr<Server> server_;
};

}  // namespace macsim
