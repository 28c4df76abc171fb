// Simulation control over DDS: pause, run, real-time factor, lock-step, load world, features.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world_loader.h"
#include "reply_cache.h"
#include "step_conditions.h"

namespace macsim {

/// Serves SimulationRequests by queueing them to the runner; a SIM_STEP request is answered
/// once its last step's data is out, a SIM_LOAD_WORLD once the new world runs (or was refused).
class SimulationServer {
 public:
  /// Worlds loaded on request are held to `limits`; step conditions read `readings`.
  SimulationServer(dds::Participant& participant, Runner& runner, LoadLimits limits = {},
                   LatestReadings readings = {});
  ~SimulationServer();

 private:
  using Request = macsim_msgs::msg::dds_::SimulationRequest_;
  using Reply = macsim_msgs::msg::dds_::SimulationReply_;

  void execute(const Request& request);
  Reply reply_to(const Request& request, int code, const std::string& message) const;
  void send(const Reply& reply);
  /// True (and answered again) if the client sent this request before.
  bool repeated(const Request& request);

  Runner& runner_;
  const LoadLimits limits_;
  const LatestReadings readings_;
  std::optional<Request> stepping_;  // the SIM_STEP request being served
  ReplyCache<Reply> replied_;
  std::mutex loads_mutex_;                     // guards last_load_ (Fast DDS's threads)
  std::map<std::string, uint64_t> last_load_;  // by client: the last load request's number
  dds::Writer<macsim_msgs::msg::dds_::SimulationReply_PubSubType> replies_;
  std::unique_ptr<dds::Reader<macsim_msgs::msg::dds_::SimulationRequest_PubSubType>> requests_;
};

}  // namespace macsim
