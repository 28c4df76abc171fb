// What this process sent to robots, in DDS's numbering. A request names the last command of
// each robot command writer of the process on its DDS domain. One that puts the world back (a reset, a
// snapshot restored, a world loaded) has the simulator drop any of them that arrives after it:
// nothing a controller sent before a reset acts after it, whatever order DDS delivers them in.
// A step request has the simulator wait for them before its first step (lock-step by contract:
// the controller need not wait for DDS to acknowledge its commands).
#pragma once

#include <array>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgs.h"

namespace macsim::client {

/// Notes a robot command written on DDS domain `domain` (CommandWriter does it for each sample
/// it writes to a matched reader: one written to none never arrives).
void note_command_sent(const dds::SampleId& sent, int domain);
/// Forgets a writer deleted (its samples can no longer arrive anywhere): CommandWriter's end.
void forget_commands_of(const std::array<uint8_t, 16>& writer);
/// The last command each robot command writer of this process (on `domain`, if given) wrote, as
/// requests carry them (at most 64 writers are kept: those noted longest ago give way).
std::vector<macsim_msgs::msg::dds_::SampleIdentity_> commands_sent(std::optional<int> domain = std::nullopt);

/// True for a request that puts the world back (OP_RESET, OP_RESTORE_SNAPSHOT).
bool puts_world_back(const macsim_msgs::msg::dds_::SupervisorRequest_& request);
/// True for a request that puts the world back (SIM_LOAD_WORLD).
bool puts_world_back(const macsim_msgs::msg::dds_::SimulationRequest_& request);
/// True for a request that carries commands_sent (those that put the world back).
bool names_commands_sent(const macsim_msgs::msg::dds_::SupervisorRequest_& request);
/// True for a request that carries commands_sent (SIM_LOAD_WORLD, SIM_STEP).
bool names_commands_sent(const macsim_msgs::msg::dds_::SimulationRequest_& request);

/// A robot command topic's writer that notes what it writes (the client's robot handles).
template <class PubSubType>
class CommandWriter {
 public:
  CommandWriter(dds::Participant& participant, const std::string& topic)
      : writer_(participant, topic, dds::QosFamily::Command), domain_(participant.domain()) {}
  ~CommandWriter() {
    if (written_) forget_commands_of(*written_);
  }
  CommandWriter(const CommandWriter&) = delete;
  CommandWriter& operator=(const CommandWriter&) = delete;
  /// Publishes one command; false if Fast DDS refused it.
  bool write(const typename PubSubType::type& command) {
    dds::SampleId sent;
    if (!writer_.write(command, sent)) return false;
    written_ = sent.writer;
    if (writer_.matched() > 0) note_command_sent(sent, domain_);
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
  int domain_;
  std::optional<std::array<uint8_t, 16>> written_;  // its GUID, once it wrote
};

}  // namespace macsim::client
