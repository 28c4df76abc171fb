// The world as a late-joining observer sees it on the world state topic.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <mutex>
#include <set>

#include "macsim/dds/participant.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"

namespace macsim::client {

/// Keeps the latest state of every object (by id) and the ids of destroyed (disposed) ones.
class WorldStateClient {
 public:
  using Objects = std::map<uint32_t, macsim_msgs::msg::dds_::ObjectState_>;

  explicit WorldStateClient(dds::Participant& participant)
      : reader_(
            participant, dds::topics::kWorldObjects, dds::QosFamily::Latched,
            [this](const macsim_msgs::msg::dds_::ObjectState_& s) {
              std::lock_guard<std::mutex> lock(mutex_);
              objects_[s.id()] = s;
            },
            [this](const macsim_msgs::msg::dds_::ObjectState_& s) {
              std::lock_guard<std::mutex> lock(mutex_);
              objects_.erase(s.id());
              destroyed_.insert(s.id());
            }) {}

  /// Waits until `check(objects, destroyed)` holds; false after `timeout`.
  bool wait(const std::function<bool(const Objects&, const std::set<uint32_t>&)>& check,
            std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (check(objects_, destroyed_)) return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }
  /// A copy of the current objects.
  Objects objects() {
    std::lock_guard<std::mutex> lock(mutex_);
    return objects_;
  }

 private:
  std::mutex mutex_;
  Objects objects_;
  std::set<uint32_t> destroyed_;
  dds::Reader<macsim_msgs::msg::dds_::ObjectState_PubSubType> reader_;
};

}  // namespace macsim::client
