// Keeps the samples a DDS topic delivers, for tests: the latest one, or all of them.
#pragma once

#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "macsim/dds/participant.h"

namespace macsim::test {

/// Subscribes to a topic and keeps every sample (up to `keep`), thread-safe.
template <class PubSubType>
class Samples {
 public:
  using Data = typename PubSubType::type;

  Samples(dds::Participant& p, const std::string& topic, std::size_t keep = 1000,
          dds::QosFamily family = dds::QosFamily::Sensor)
      : keep_(keep), reader_(p, topic, family, [this](const Data& d) {
          std::lock_guard<std::mutex> lock(mutex_);
          if (all_.size() >= keep_) all_.erase(all_.begin());
          all_.push_back(d);
        }) {}

  std::optional<Data> latest() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (all_.empty()) return std::nullopt;
    return all_.back();
  }
  std::vector<Data> all() {
    std::lock_guard<std::mutex> lock(mutex_);
    return all_;
  }
  /// Waits until `count` samples have come (or the timeout passes); true if they did.
  bool wait_for_count(std::size_t count, std::chrono::milliseconds timeout) {
    return poll([&] { return all_.size() >= count; }, timeout);
  }
  /// Waits until a sample satisfies `predicate` (or the timeout passes); returns it.
  std::optional<Data> wait_for(const std::function<bool(const Data&)>& predicate,
                               std::chrono::milliseconds timeout) {
    std::optional<Data> found;
    poll(
        [&] {
          for (auto it = all_.rbegin(); it != all_.rend() && !found; ++it) {
            if (predicate(*it)) found = *it;
          }
          return found.has_value();
        },
        timeout);
    return found;
  }

 private:
  /// Asks `done` (under the lock) every 10 ms until it says yes or the timeout passes.
  template <class Done>
  bool poll(Done done, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (done()) return true;
      }
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  std::size_t keep_;
  std::mutex mutex_;
  std::vector<Data> all_;
  dds::Reader<PubSubType> reader_;
};

}  // namespace macsim::test
