// Simulation control over DDS: pause, run, real-time factor, lock-step, load world, features.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/session.h"
#include "macsim/sim_core/world_loader.h"
#include "reply_cache.h"
#include "request_progress.h"
#include "request_service.h"
#include "simulation/step_conditions.h"

namespace macsim {

/// Serves SimulationRequests by queueing them to the runner; a SIM_STEP request is answered
/// once its last step's data is out, a SIM_LOAD_WORLD once the new world runs (or was refused).
/// Until then its client gets progress replies (ERR_IN_PROGRESS, with a step request's steps
/// done); SIM_CANCEL from the same client ends its step request.
class SimulationServer {
 public:
  /// At most this many clients' load request numbers are kept (the least recently used goes):
  /// a very late repeat of an evicted client's load could load it again.
  static constexpr std::size_t kMaxLoadClients = 1024;
  /// Per client, its last this many load request numbers are kept; a repeat of an older one is
  /// known as seen (its sequence number is below them) and never loads again.
  static constexpr std::size_t kLoadWindow = 16;

  /// What a step request wanting its data at its end kept back, on the simulation thread.
  struct HeldOutput {
    std::function<void()> flush;  ///< writes it (the runner's request_end hook does the same)
    std::function<std::vector<std::string>()> published;  ///< the topics the last write wrote
  };
  /// Worlds loaded on request are held to `limits`; step conditions read `readings`; the reply
  /// to a step request that wanted its data at its end names the topics its end wrote.
  SimulationServer(dds::Participant& participant, Runner& runner, LoadLimits limits = {},
                   LatestReadings readings = {}, HeldOutput held = {});
  ~SimulationServer();

  /// The service's name in a recorded session (its requests taken and answered).
  static constexpr const char* kSessionService = "simulation";
  /// Carries on from a resumed session's requests (on the simulation thread, before the loop):
  /// a repeat of one answered gets its reply again, a load answered never loads again, the
  /// run's pause and real-time factor are as its last reply said, and a step request taken
  /// and not answered steps on from where the world is to the end it asked for, once its
  /// client sends it again (its readers then know this process).
  void resume(const std::vector<RecordedRequest>& requests);

  /// A request a session took (began stepping) and never answered: the killed simulator had
  /// begun it.
  struct Begun {
    uint64_t step = 0;  ///< steps run when it was taken (after its first step), last
    /// The same when it was first taken: a resumed run that goes on with it takes it again.
    uint64_t first_step = 0;
    macsim_msgs::msg::dds_::SimulationRequest_ request;  ///< as taken last (its steps left)
  };
  /// The requests `requests` (a session's) took and never answered, in the order taken.
  static std::vector<Begun> begun(const std::vector<RecordedRequest>& requests);

 private:
  using Request = macsim_msgs::msg::dds_::SimulationRequest_;
  using Reply = macsim_msgs::msg::dds_::SimulationReply_;

  /// Runs a request that is no repeat (the executor answers repeats with repeated()).
  void execute(const Request& request);
  /// SIM_CANCEL: ends the client's step request it names, if that is the one running.
  Reply cancel(const Request& request);
  /// True if this client's load request was seen before (and remembers it if not).
  bool load_seen(const Request& request);
  /// Forgets that this client's load request was seen (it was refused before it was queued).
  void forget_load(const Request& request);
  Reply reply_to(const Request& request, int code, const std::string& message) const;
  /// Answers: remembered for repeats, written to a recorded session first unless `query`.
  void send(const Reply& reply, bool query = false);
  /// Remembers that this client's load request was seen.
  void remember_load(const std::string& client_id, uint64_t sequence_number);
  /// Answers a request the runner's queue refused, from the listener: ERR_LIMIT_REACHED (not
  /// kept for repeats: a repeat is tried again).
  void refuse_full(const Request& request);
  /// True (and answered again) if the client sent this request before.
  bool repeated(const Request& request);

  Runner& runner_;
  const LoadLimits limits_;
  const LatestReadings readings_;
  const HeldOutput held_;
  /// held_.published(), within the reply field's bound.
  std::vector<std::string> published() const;
  std::optional<Request> stepping_;  // the SIM_STEP request being served
  bool cancelling_ = false;          // a SIM_CANCEL is ending stepping_
  std::optional<Reply> cancelled_;   // the reply of the request it ended
  /// Step requests a killed run had begun, their steps left: run when their client repeats.
  std::map<std::pair<std::string, uint64_t>, Request> resumable_;
  ReplyCache<Reply> replied_;
  std::mutex loads_mutex_;  // guards loads_seen_ and load_uses_ (Fast DDS's threads)
  struct LoadsSeen {
    std::set<uint64_t> recent;       // the last kLoadWindow load request numbers
    uint64_t forgotten_through = 0;  // every load request number up to this one was seen
    uint64_t use = 0;                // load_uses_ when last seen
  };
  std::map<std::string, LoadsSeen> loads_seen_;  // by client, at most kMaxLoadClients
  uint64_t load_uses_ = 0;
  RequestService<macsim_msgs::msg::dds_::SimulationRequest_PubSubType,
                 macsim_msgs::msg::dds_::SimulationReply_PubSubType>
      service_;                      // requests in, replies out; closed first
  RequestProgress<Reply> progress_;  // writes through service_
};

}  // namespace macsim
