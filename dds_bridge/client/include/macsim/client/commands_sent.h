// What this process sent to robots, in DDS's numbering. A request that puts the world back (a
// reset, a snapshot restored, a world loaded) names the last command of each of the process's
// robot command writers, and the simulator drops any of them that arrives after the request:
// nothing a controller sent before a reset acts after it, whatever order DDS delivers them in.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgs.h"

namespace macsim::client {

/// Notes a robot command written (CommandWriter does it for each sample it writes).
void note_command_sent(const dds::SampleId& sent);
/// The last command each robot command writer of this process wrote, as requests carry them
/// (at most 64: the writers noted longest ago give way).
std::vector<macsim_msgs::msg::dds_::SampleIdentity_> commands_sent();

/// True for a request that puts the world back (OP_RESET, OP_RESTORE_SNAPSHOT).
bool puts_world_back(const macsim_msgs::msg::dds_::SupervisorRequest_& request);
/// True for a request that puts the world back (SIM_LOAD_WORLD).
bool puts_world_back(const macsim_msgs::msg::dds_::SimulationRequest_& request);

/// A robot command topic's writer that notes what it writes (the client's robot handles).
template <class PubSubType>
class CommandWriter {
 public:
  CommandWriter(dds::Participant& participant, const std::string& topic)
      : writer_(participant, topic, dds::QosFamily::Command) {}
  /// Publishes one command; false if Fast DDS refused it.
  bool write(const typename PubSubType::type& command) {
    dds::SampleId sent;
    if (!writer_.write(command, sent)) return false;
    note_command_sent(sent);
    return true;
  }
  /// Waits until every matched reader acknowledged what was written.
  bool wait_acknowledged(std::chrono::milliseconds timeout) {
    return writer_.wait_acknowledged(timeout);
  }
  /// Number of readers currently matched.
  int matched() const { return writer_.matched(); }
  /// Readers matched so far, those gone included (a simulator restarted brings a new one).
  int readers_seen() const { return writer_.matched_ever(); }

 private:
  dds::Writer<PubSubType> writer_;
};

}  // namespace macsim::client
