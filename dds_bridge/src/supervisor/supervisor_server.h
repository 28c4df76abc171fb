// The supervisor over DDS: requests in (queued for the simulation thread), replies out; the
// world state (one instance per object), door states and events out.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/sim_core/runner.h"
#include "reply_cache.h"
#include "request_progress.h"
#include "request_service.h"

namespace macsim {

/// Serves sim_core's supervisor operations. Requests are executed on the simulation thread,
/// between two steps, in arrival order; each gets exactly one reply (and progress replies,
/// ERR_IN_PROGRESS, while it waits behind a long step or a world load).
class SupervisorServer {
 public:
  SupervisorServer(dds::Participant& participant, Runner& runner);
  ~SupervisorServer();

  /// Publishes the world state every 0.1 s of sim time, and the events of the last step.
  void publish();
  /// Writes the world's state if publish() kept it back (a step request wanting its data at
  /// its end).
  void flush();
  /// Topic names it serves, for the start-up banner.
  static std::vector<std::string> topic_names();

  using Request = macsim_msgs::msg::dds_::SupervisorRequest_;
  using Reply = macsim_msgs::msg::dds_::SupervisorReply_;
  /// A resumed run's replies to the requests that changed the world before the kill, oldest
  /// first (on the simulation thread, before the loop): a repeat gets its reply, runs nothing.
  void remember(const std::vector<Reply>& replies);

 private:
  /// Runs a request (not one answered before; `command` its queued form); true when it reached
  /// the world, which a recorded session then holds before the reply goes out. The reply names
  /// the request's sample identity `id` too, when there is one.
  bool execute(const Request& request, World& world, const dds::RequestId* id,
               const Command& command);
  /// Answers a repeat of a request already run (its reply sent again, or that it is too old to
  /// run again); false for a request not run before.
  bool answer_repeat(const Request& request, const dds::RequestId* id);
  /// Answers a request that was not queued, from the listener (nothing of the world read; not
  /// kept for repeats: a repeat is tried again).
  void refuse(const Request& request, const dds::RequestId& id, int code,
              const std::string& message);
  void publish_world_state(World& world);

  Runner& runner_;
  double next_state_time_ = 0.0;
  bool state_held_ = false;  // due while a step request wanted its data at its end
  double last_time_ = 0.0;
  uint64_t generation_ = 0;  // of the world published_ids_ belong to
  std::set<uint32_t> published_ids_;
  std::set<std::string> published_doors_;
  ReplyCache<Reply> replied_;
  dds::Writer<macsim_msgs::msg::dds_::ObjectState_PubSubType> objects_;
  dds::Writer<macsim_msgs::msg::dds_::DoorState_PubSubType> doors_;
  dds::Writer<macsim_msgs::msg::dds_::WorldEvent_PubSubType> events_;
  // the same, unkeyed and stamped the ROS way
  dds::Writer<macsim_msgs::msg::dds_::ObjectList_PubSubType> object_list_;
  dds::Writer<macsim_msgs::msg::dds_::DoorList_PubSubType> door_list_;
  dds::Writer<macsim_msgs::msg::dds_::Event_PubSubType> events_stamped_;
  RequestService<macsim_msgs::msg::dds_::SupervisorRequest_PubSubType,
                 macsim_msgs::msg::dds_::SupervisorReply_PubSubType>
      service_;                      // requests in, replies out; closed first
  RequestProgress<Reply> progress_;  // writes through service_
};

}  // namespace macsim
