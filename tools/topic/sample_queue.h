// Samples received and not yet stored (macsim_topic record), held to a budget of bytes: each
// sample counts with its buffer's capacity and its bookkeeping, and a batch taken to be written
// stays counted until it is written.
#pragma once

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>

#include "raw_endpoints.h"

namespace macsim::topic {

/// A queue of received samples of at most `max_bytes` (as cost() counts them); thread-safe.
class SampleQueue {
 public:
  /// One queued sample and the topic (bag id) it came on.
  struct Entry {
    int topic = 0;
    ReceivedSample sample;
  };
  using Batch = std::deque<Entry>;

  /// Bytes a heap block costs beyond what it holds (glibc's chunk header and rounding).
  static constexpr std::size_t kAllocatorOverhead = 32;

  explicit SampleQueue(std::size_t max_bytes) : max_bytes_(max_bytes) {}

  /// What one queued sample is counted for: its entry, its buffer's capacity, an allocation.
  static std::size_t cost(const ReceivedSample& sample) {
    return sizeof(Entry) + sample.bytes.capacity() + kAllocatorOverhead;
  }
  /// Queues the sample; false (dropped, counted in dropped()) if it does not fit.
  bool push(int topic, ReceivedSample&& sample) {
    const std::size_t bytes = cost(sample);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (bytes > max_bytes_ - std::min(bytes_, max_bytes_)) {
        ++dropped_;
        return false;
      }
      bytes_ += bytes;
      queue_.push_back({topic, std::move(sample)});
    }
    ready_.notify_one();
    return true;
  }
  /// Takes what is queued, waiting up to `wait` for a first sample; the batch stays counted
  /// until release().
  Batch take(std::chrono::milliseconds wait) {
    Batch batch;
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait_for(lock, wait, [&] { return !queue_.empty(); });
    batch.swap(queue_);
    return batch;
  }
  /// A batch take() gave was stored (or given up): its bytes are free again.
  void release(const Batch& batch) {
    std::size_t bytes = 0;
    for (const Entry& e : batch) bytes += cost(e.sample);
    std::lock_guard<std::mutex> lock(mutex_);
    bytes_ -= std::min(bytes, bytes_);
  }
  /// Bytes counted now: queued, and taken but not released.
  std::size_t bytes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return bytes_;
  }
  /// Samples push() refused so far.
  std::uint64_t dropped() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }

 private:
  const std::size_t max_bytes_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  Batch queue_;
  std::size_t bytes_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace macsim::topic
