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
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (all_.size() >= count) return true;
      }
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  /// Waits until a sample satisfies `predicate` (or the timeout passes); returns it.
  std::optional<Data> wait_for(const std::function<bool(const Data&)>& predicate,
                               std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = all_.rbegin(); it != all_.rend(); ++it) {
          if (predicate(*it)) return *it;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return std::nullopt;
  }

 private:
  std::size_t keep_;
  std::mutex mutex_;
  std::vector<Data> all_;
  dds::Reader<PubSubType> reader_;
};

}  // namespace macsim::test
