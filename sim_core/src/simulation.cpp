#include "macsim/sim_core/simulation.h"

namespace macsim {

void CommandQueue::push(Command command) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_.push_back(std::move(command));
  }
  arrived_.notify_one();
}

bool CommandQueue::wait_until(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  return arrived_.wait_until(lock, deadline, [this] { return !pending_.empty(); });
}

std::size_t CommandQueue::drain(World& world) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    running_.swap(pending_);
  }
  for (auto& command : running_) command(world);
  const std::size_t ran = running_.size();
  running_.clear();
  return ran;
}

}  // namespace macsim
