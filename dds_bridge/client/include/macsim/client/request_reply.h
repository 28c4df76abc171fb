// Calls over a request/reply topic pair correlated in the payload (client id + sequence
// number), so any DDS implementation can serve or call them.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "macsim/dds/participant.h"

namespace macsim::client {

/// Sends requests with this client's id and the next sequence number, waits for the reply that
/// echoes both; resends every second until answered (servers answer a repeat without redoing).
template <class RequestPubSub, class ReplyPubSub>
class RequestReply {
 public:
  using Request = typename RequestPubSub::type;
  using Reply = typename ReplyPubSub::type;

  RequestReply(dds::Participant& participant, const std::string& request_topic,
               const std::string& reply_topic, std::string client_id)
      : client_id_(client_id.empty()
                       ? "client-" + std::to_string(::getpid()) + "-" +
                             std::to_string(reinterpret_cast<uintptr_t>(this) % 100000)
                       : std::move(client_id)),
        requests_(participant, request_topic, dds::QosFamily::Command),
        replies_(participant, reply_topic, dds::QosFamily::Command, [this](const Reply& r) {
          std::lock_guard<std::mutex> lock(mutex_);
          if (r.client_id() != client_id_ || r.sequence_number() != waiting_for_) return;
          reply_ = r;
          replied_.notify_all();
        }) {}

  /// Asked at least every 100 ms while a call waits: true gives up at once (a Ctrl-C).
  using Interrupted = std::function<bool()>;

  /// Sends `request` and waits for its reply; nullopt if none came within `timeout` (or
  /// `interrupted` said so).
  std::optional<Reply> call(Request request,
                            std::chrono::milliseconds timeout = std::chrono::seconds(10),
                            const Interrupted& interrupted = {}) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    if (!wait_for_server(timeout, interrupted)) return std::nullopt;
    request.client_id(client_id_);
    request.sequence_number(next_sequence_++);
    std::unique_lock<std::mutex> lock(mutex_);
    waiting_for_ = request.sequence_number();
    reply_.reset();
    while (std::chrono::steady_clock::now() < deadline) {
      lock.unlock();
      requests_.write(request);
      lock.lock();
      const auto retry =
          std::min(deadline, std::chrono::steady_clock::now() + std::chrono::seconds(1));
      // Without an interruption to look for, one wait to the retry; with one, slices of it.
      while (std::chrono::steady_clock::now() < retry) {
        const auto until =
            interrupted ? std::min(retry, std::chrono::steady_clock::now() + kSlice) : retry;
        if (replied_.wait_until(lock, until, [this] { return reply_.has_value(); })) return reply_;
        if (interrupted) {
          lock.unlock();
          const bool stop = interrupted();
          lock.lock();
          if (stop) return std::nullopt;
        }
      }
    }
    return std::nullopt;
  }

  /// Waits until a server is matched both ways.
  bool wait_for_server(std::chrono::milliseconds timeout, const Interrupted& interrupted = {}) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (int polls = 1; requests_.matched() == 0 || replies_.matched() == 0; ++polls) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      if (interrupted && polls % 5 == 0 && interrupted()) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }

  const std::string& client_id() const { return client_id_; }

 private:
  static constexpr std::chrono::milliseconds kSlice{100};
  std::string client_id_;
  uint64_t next_sequence_ = 1;
  std::mutex mutex_;
  std::condition_variable replied_;
  std::optional<Reply> reply_;
  uint64_t waiting_for_ = 0;
  dds::Writer<RequestPubSub> requests_;
  dds::Reader<ReplyPubSub> replies_;
};

}  // namespace macsim::client
