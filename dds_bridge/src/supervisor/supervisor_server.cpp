#include "supervisor/supervisor_server.h"

#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "macsim/dds/wire.h"
#include "supervisor/supervisor_codec.h"
#include "supervisor/supervisor_dispatch.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;
using dds::QosFamily;

SupervisorServer::SupervisorServer(dds::Participant& participant, Runner& runner)
    : runner_(runner),
      objects_(participant, dds::topics::kWorldObjects, QosFamily::Latched),
      doors_(participant, dds::topics::kWorldDoors, QosFamily::Latched),
      events_(participant, dds::topics::kWorldEvents, QosFamily::Command),
      object_list_(participant, dds::topics::kWorldObjectList, QosFamily::Latched),
      door_list_(participant, dds::topics::kWorldDoorList, QosFamily::Latched),
      events_stamped_(participant, dds::topics::kWorldEventsStamped, QosFamily::Command),
      progress_([this](const Reply& reply) { service_.reply(reply); }) {
  // On the simulation thread, live or in a replay: the request from its wire form.
  runner_.set_executor<SupervisorCall>(
      [this](const SupervisorCall& call, const Command& c, World& world) {
        const auto* reply_to = std::any_cast<dds::RequestId>(&c.reply_to);
        if (answer_repeat(call.message(), reply_to)) {
          runner_.answered_repeat(c);
          return false;
        }
        return execute(call.message(), world, reply_to, c);
      });
  // On Fast DDS's thread: copy the request and queue it; the world is touched only later. A
  // repeat of a request still waiting gets its progress and is not queued again.
  service_.open(participant,
                dds::ServiceTopics{dds::topics::kSupervisorRequest, dds::topics::kSupervisorReply},
                [this](const Request& r, const dds::RequestId& id) {
                  if (!progress_.begin(r,
                                       "waiting for the simulation thread (a step or a world load "
                                       "before it)")) {
                    return;
                  }
                  Command c = supervisor_command(r);
                  c.reply_to = id;
                  if (!runner_.push(std::move(c))) {
                    refuse(r, id, mm::ERR_LIMIT_REACHED, runner_.queue_full_message());
                  }
                });
}

SupervisorServer::~SupervisorServer() {
  service_.close();
  runner_.set_executor<SupervisorCall>({});  // what is still queued runs nowhere
}

void SupervisorServer::refuse(const Request& q, const dds::RequestId& id, int code,
                              const std::string& message) {
  Reply reply;
  reply.client_id(q.client_id());
  reply.sequence_number(q.sequence_number());
  reply.code(code);
  reply.message(message);
  progress_.end(q.client_id(), q.sequence_number());
  service_.reply(reply, &id);
}

void SupervisorServer::remember(const std::vector<Reply>& replies) {
  for (const Reply& reply : replies) replied_.remember(reply);
}

bool SupervisorServer::answer_repeat(const Request& q, const dds::RequestId* id) {
  if (const Reply* again = replied_.find(q)) {  // sent again: answer, do not redo
    progress_.end(q.client_id(), q.sequence_number());
    service_.reply(*again, id);
    return true;
  }
  if (replied_.forgotten(q)) {  // answered long ago: its reply is gone, it must not run again
    progress_.end(q.client_id(), q.sequence_number());
    service_.reply(replied_.forgotten_reply(q), id);
    return true;
  }
  return false;
}

bool SupervisorServer::execute(const Request& q, World& world, const dds::RequestId* id,
                               const Command& command) {
  const Reply reply = dispatch(q, world, runner_.snapshots());
  const bool changed = changes_world(q.operation()._d());
  if (changed) runner_.record_now(command);  // in the session before its client hears of it
  progress_.end(q.client_id(), q.sequence_number());
  replied_.remember(reply);
  service_.reply(reply, id);
  return changed;
}

void SupervisorServer::publish_world_state(World& world) {
  const double now = world.time();
  if (runner_.generation() != generation_) {
    // Ids and doors belong to one world: every instance of the old world goes.
    for (uint32_t gone : published_ids_) {
      mm::ObjectState_ state;
      state.id(gone);
      objects_.dispose(state);
    }
    published_ids_.clear();
    for (const std::string& gone : published_doors_) {
      mm::DoorState_ state;
      state.name(gone);
      doors_.dispose(state);
    }
    published_doors_.clear();
    generation_ = runner_.generation();
  }
  std::set<uint32_t> present;
  // The lists cost a copy of the world: built only while someone reads them.
  const bool lists = object_list_.matched() > 0 || door_list_.matched() > 0;
  mm::ObjectList_ list;
  list.header(dds::header(now, "world"));
  for (ObjectId id : world.objects().object_ids()) {
    mm::ObjectState_ state;
    state.id(id);
    state.stamp(now);
    state.object(codec::object_message(world, id));
    objects_.write(state);
    if (lists) list.objects().push_back(state.object());
    present.insert(id);
  }
  if (lists) object_list_.write(list);
  for (uint32_t gone : published_ids_) {
    if (present.count(gone)) continue;
    mm::ObjectState_ state;
    state.id(gone);
    objects_.dispose(state);  // the object was destroyed: its instance goes too
  }
  published_ids_ = std::move(present);
  std::set<std::string> doors;
  mm::DoorList_ door_list;
  door_list.header(dds::header(now, "world"));
  for (int d = 0; d < world.doors().door_count(); ++d) {
    mm::DoorState_ state;
    state.name(world.doors().door_name(d));
    state.stamp(now);
    state.door(codec::door_message(world, d));
    doors_.write(state);
    if (lists) door_list.doors().push_back(state.door());
    doors.insert(state.name());
  }
  if (lists) door_list_.write(door_list);
  for (const std::string& gone : published_doors_) {
    if (doors.count(gone)) continue;
    mm::DoorState_ state;
    state.name(gone);
    doors_.dispose(state);  // the door was destroyed: its instance goes too
  }
  published_doors_ = std::move(doors);
}

std::vector<std::string> SupervisorServer::topic_names() {
  return {dds::topics::kSupervisorRequest + " (macsim_msgs/SupervisorRequest, in)",
          dds::topics::kSupervisorReply + " (macsim_msgs/SupervisorReply, out)",
          dds::topics::kWorldObjects + " (macsim_msgs/ObjectState, keyed by object id, out)",
          dds::topics::kWorldDoors + " (macsim_msgs/DoorState, keyed by door name, out)",
          dds::topics::kWorldEvents + " (macsim_msgs/WorldEvent, out)",
          dds::topics::kWorldObjectList + " (macsim_msgs/ObjectList, unkeyed, latched, out)",
          dds::topics::kWorldDoorList + " (macsim_msgs/DoorList, unkeyed, latched, out)",
          dds::topics::kWorldEventsStamped + " (macsim_msgs/Event, out)"};
}

void SupervisorServer::publish() {
  World& world = runner_.world();
  for (const auto& e : world.take_events()) {
    mm::WorldEvent_ event;
    event.stamp(e.time);
    event.type(codec::event_name(e.type));
    event.subject(e.subject);
    event.detail(e.detail);
    events_.write(event);
    mm::Event_ stamped;
    stamped.header(dds::header(e.time, "world"));
    stamped.type(event.type());
    stamped.subject(event.subject());
    stamped.detail(event.detail());
    events_stamped_.write(stamped);
  }
  if (world.time() < last_time_ || runner_.generation() != generation_) {
    next_state_time_ = world.time();  // a reset or a new world: publish its state now
  }
  last_time_ = world.time();
  if (world.time() + 1e-9 >= next_state_time_) {
    next_state_time_ = world.time() + 0.1;
    const StepRequest* request = runner_.step_request();
    state_held_ = request && request->publish_at_end;
    if (!state_held_) publish_world_state(world);
  }
}

void SupervisorServer::flush() {
  if (!state_held_) return;
  state_held_ = false;
  publish_world_state(runner_.world());
}

}  // namespace macsim
