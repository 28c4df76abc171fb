// The world as macsim publishes it, seen by a test: objects by name (their newest state), the
// doors, and the robot's ground truth (every sample, for its path).
#pragma once

#include <map>
#include <mutex>
#include <string>

#include "macsim/dds/topics.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "support/latest_sample.h"

namespace macsim::test {

struct WorldView {
  explicit WorldView(dds::Participant& p, const std::string& robot = "kurt")
      : objects_(p, dds::topics::kWorldObjects, dds::QosFamily::Latched,
                 [this](const macsim_msgs::msg::dds_::ObjectState_& s) {
                   std::lock_guard<std::mutex> lock(mutex_);
                   objects[s.object().name()] = s.object();
                 }),
        doors(p, dds::topics::kWorldDoors),
        truth(p, dds::topics::ground_truth(robot), 100000) {}

  /// The objects' newest states, by name.
  std::map<std::string, macsim_msgs::msg::dds_::Object_> snapshot() {
    std::lock_guard<std::mutex> lock(mutex_);
    return objects;
  }

  std::mutex mutex_;
  std::map<std::string, macsim_msgs::msg::dds_::Object_> objects;
  dds::Reader<macsim_msgs::msg::dds_::ObjectState_PubSubType> objects_;
  Samples<macsim_msgs::msg::dds_::DoorState_PubSubType> doors;
  Samples<nav_msgs::msg::dds_::Odometry_PubSubType> truth;
};

}  // namespace macsim::test
