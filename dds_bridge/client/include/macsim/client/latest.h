// The latest sample of a topic, with a count to wait on: what a controller reads its sensors by.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "macsim/dds/participant.h"

namespace macsim::client {

/// Subscribes to one topic and keeps its latest sample (thread-safe; the sample is copied once,
/// on arrival, and shared from then on).
template <class PubSubType>
class Latest {
 public:
  using Data = typename PubSubType::type;

  Latest(dds::Participant& participant, const std::string& topic,
         dds::QosFamily family = dds::QosFamily::Sensor)
      : reader_(participant, topic, family, [this](const Data& sample) {
          auto copy = std::make_shared<const Data>(sample);
          {
            std::lock_guard<std::mutex> lock(mutex_);
            latest_ = std::move(copy);
            ++count_;
          }
          arrived_.notify_all();
        }) {}

  /// The latest sample, if any came.
  std::optional<Data> get() const {
    auto latest = get_shared();
    if (!latest) return std::nullopt;
    return *latest;
  }
  /// The latest sample without a copy (shared with the reader), or null if none came.
  std::shared_ptr<const Data> get_shared() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
  }
  /// Forgets the latest sample (after a world reset sim time starts again, so stamps repeat);
  /// count() goes on.
  void forget() {
    std::lock_guard<std::mutex> lock(mutex_);
    latest_.reset();
  }
  /// How many samples came so far.
  uint64_t count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return count_;
  }
  /// Waits until more than `seen` samples came; the latest one, or nothing after `timeout`.
  std::optional<Data> wait_after(uint64_t seen, std::chrono::milliseconds timeout) const {
    auto latest = wait_shared_after(seen, timeout);
    if (!latest) return std::nullopt;
    return *latest;
  }
  /// wait_after() without a copy: the latest sample, or null after `timeout`.
  std::shared_ptr<const Data> wait_shared_after(uint64_t seen,
                                                std::chrono::milliseconds timeout) const {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!arrived_.wait_for(lock, timeout, [&] { return count_ > seen; })) return nullptr;
    return latest_;
  }
  /// Number of writers matched.
  int matched() const { return reader_.matched(); }
  /// Writers matched so far, those gone included (a simulator restarted brings new ones).
  int writers_seen() const { return reader_.matched_ever(); }

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable arrived_;
  std::shared_ptr<const Data> latest_;
  uint64_t count_ = 0;
  dds::Reader<PubSubType> reader_;
};

}  // namespace macsim::client
