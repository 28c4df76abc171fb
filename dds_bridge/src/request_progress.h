// Progress replies of every request/reply service: a request not answered within a short time
// gets replies with code ERR_IN_PROGRESS (same client id and sequence number) until its final
// reply goes out, sent from a thread of their own, so that a client can tell a busy server (one
// long step, a world load) from one that is gone. A repeat of a request still running is
// answered with its progress, never run again.
#pragma once

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "macsim/msg/macsim_msgs.h"

namespace macsim {

/// Requests received and not answered yet; `Reply` has client_id(), sequence_number(), code(),
/// message().
template <class Reply>
class RequestProgress {
 public:
  /// Fills a progress reply with what its request did so far (called on the progress thread).
  using Fill = std::function<void(Reply&)>;

  /// The first progress reply goes out this long after the request came, by default.
  static constexpr std::chrono::milliseconds kFirst{200};
  /// Then one every this long, by default.
  static constexpr std::chrono::milliseconds kEvery{300};
  /// At most this many requests are followed; more are served without progress replies.
  static constexpr std::size_t kMaxFollowed = 1024;

  /// `write` sends a reply (from the progress thread, or from begin()'s caller for a repeat);
  /// the first progress goes `first` after a request came, then one every `every`.
  explicit RequestProgress(std::function<void(const Reply&)> write,
                           std::chrono::milliseconds first = kFirst,
                           std::chrono::milliseconds every = kEvery)
      : write_(std::move(write)), first_(first), every_(every), thread_([this] { loop(); }) {}
  ~RequestProgress() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  RequestProgress(const RequestProgress&) = delete;
  RequestProgress& operator=(const RequestProgress&) = delete;

  /// Follows a request that just came, described by `what` ("waiting for ..."); false if it is
  /// a repeat of one still followed: it must not run again, and its progress is sent now (if
  /// it came `first` ago or more: a client resending at once hears its progress on schedule).
  template <class Request>
  bool begin(const Request& request, std::string what, Fill fill = {}) {
    std::lock_guard<std::mutex> lock(mutex_);
    const Key key{request.client_id(), request.sequence_number()};
    if (const auto running = followed_.find(key); running != followed_.end()) {
      const auto now = Clock::now();
      if (now - running->second.came >= first_) send(key, running->second, now);
      return false;
    }
    if (followed_.size() < kMaxFollowed) {
      followed_.emplace(key, Followed{Clock::now(), {}, std::move(what), std::move(fill)});
    }
    return true;
  }
  /// What a followed request does now and how far it got.
  void update(const std::string& client_id, uint64_t sequence_number, std::string what,
              Fill fill = {}) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto f = followed_.find(Key{client_id, sequence_number});
    if (f == followed_.end()) return;
    f->second.what = std::move(what);
    f->second.fill = std::move(fill);
  }
  /// The request is answered (call right before its final reply is written): no progress
  /// reply for it goes out after this returns.
  void end(const std::string& client_id, uint64_t sequence_number) {
    std::lock_guard<std::mutex> lock(mutex_);
    followed_.erase(Key{client_id, sequence_number});
  }

 private:
  using Clock = std::chrono::steady_clock;
  using Key = std::pair<std::string, uint64_t>;
  struct Followed {
    Clock::time_point came;
    Clock::time_point last_sent;  // epoch: none yet
    std::string what;
    Fill fill;
  };

  void send(const Key& key, Followed& f, Clock::time_point now) {
    Reply reply;
    reply.client_id(key.first);
    reply.sequence_number(key.second);
    reply.code(macsim_msgs::msg::dds_::ERR_IN_PROGRESS);
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now - f.came).count();
    reply.message(f.what + ", " + std::to_string(ms / 1000) + "." +
                  std::to_string(ms % 1000 / 100) + " s after it came");
    if (f.fill) f.fill(reply);
    write_(reply);
    f.last_sent = now;
  }

  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      wake_.wait_for(lock, std::clamp(every_, std::chrono::milliseconds(1),
                                      std::chrono::milliseconds(50)));
      if (stop_) break;
      const auto now = Clock::now();
      // Written under the lock: once end() returned, no progress of that request goes out.
      for (auto& [key, f] : followed_) {
        const bool none_yet = f.last_sent == Clock::time_point{};
        if (now - f.came >= first_ && (none_yet || now - f.last_sent >= every_)) {
          send(key, f, now);
        }
      }
    }
  }

  std::function<void(const Reply&)> write_;
  const std::chrono::milliseconds first_;
  const std::chrono::milliseconds every_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::map<Key, Followed> followed_;
  std::thread thread_;  // last: starts once the rest is built
};

}  // namespace macsim
