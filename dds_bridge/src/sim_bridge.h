// Maps one Simulation onto DDS topics: commands in (queued), clock and robot data out.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/msg/geometry_msgs.h"
#include "macsim/msg/geometry_msgsPubSubTypes.h"
#include "macsim/msg/nav_msgs.h"
#include "macsim/msg/nav_msgsPubSubTypes.h"
#include "macsim/msg/rosgraph_msgs.h"
#include "macsim/msg/rosgraph_msgsPubSubTypes.h"
#include "macsim/sim_core/simulation.h"

namespace macsim {

/// Serves a simulation over DDS. Reader callbacks only push commands onto the simulation's
/// queue; publish() runs on the simulation thread after each step.
class SimBridge {
 public:
  SimBridge(dds::Participant& participant, Simulation& simulation);
  ~SimBridge();

  /// Publishes what the last step produced (clock and odometry every 10 ms of sim time).
  void publish();
  /// Topic names this bridge serves, for the start-up banner.
  std::vector<std::string> topic_names() const;

 private:
  struct RobotTopics;
  Simulation& simulation_;
  double next_clock_time_ = 0.0;
  std::unique_ptr<dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType>> clock_;
  std::vector<std::unique_ptr<RobotTopics>> robots_;
};

}  // namespace macsim
