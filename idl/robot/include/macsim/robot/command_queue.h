// A thread-safe FIFO of commands: producers (e.g. DDS callbacks) only push; the owner's thread
// runs them all at one point of its loop. Header-only, no ODE: the simulation and the real
// robot's adapter both use it.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <utility>
#include <vector>

namespace macsim {

/// Commands taking `Args` (what they act on), run in arrival order by drain().
template <class... Args>
class BasicCommandQueue {
 public:
  using Command = std::function<void(Args...)>;

  /// Queues a command; any thread.
  void push(Command command) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pending_.push_back(std::move(command));
    }
    arrived_.notify_one();
  }
  /// Runs every queued command, in arrival order; returns how many ran. The owner's thread.
  std::size_t drain(Args... args) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      running_.swap(pending_);
    }
    for (auto& command : running_) command(args...);
    const std::size_t ran = running_.size();
    running_.clear();
    return ran;
  }
  /// Blocks until a command is queued or `deadline` passes; true if commands wait.
  bool wait_until(std::chrono::steady_clock::time_point deadline) {
    std::unique_lock<std::mutex> lock(mutex_);
    return arrived_.wait_until(lock, deadline, [this] { return !pending_.empty(); });
  }

 private:
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<Command> pending_;
  std::vector<Command> running_;
};

}  // namespace macsim
