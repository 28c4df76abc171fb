#include "simulation_server.h"

#include <cmath>

#include "macsim/dds/topics.h"
#include "macsim/sim_core/world_loader.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

SimulationServer::SimulationServer(dds::Participant& participant, Simulation& simulation,
                                   LoopControl initial)
    : simulation_(simulation),
      control_(initial),
      replies_(participant, dds::topics::kSimulationReply, dds::QosFamily::Command) {
  // On Fast DDS's thread: queue the request; it runs on the simulation thread.
  requests_ = std::make_unique<dds::Reader<mm::SimulationRequest_PubSubType>>(
      participant, dds::topics::kSimulationRequest, dds::QosFamily::Command,
      [this](const Request& r) {
        simulation_.commands().push([this, r](World&) { execute(r); });
      });
}

SimulationServer::~SimulationServer() { requests_.reset(); }

SimulationServer::Reply SimulationServer::reply_to(const Request& q, int code,
                                                   const std::string& message) const {
  Reply r;
  r.client_id(q.client_id());
  r.sequence_number(q.sequence_number());
  r.code(code);
  r.message(message);
  const World& world = simulation_.world();
  r.sim_time(world.time());
  r.steps(world.steps());
  r.state_hash(world.state_hash());
  r.paused(control_.paused);
  r.real_time_factor(control_.real_time_factor);
  r.features("simulator,supervisor,lockstep,ground_truth,reset,snapshot,load_world,cameras,laser,crane");
  return r;
}

void SimulationServer::execute(const Request& q) {
  // A client that did not hear its reply sends the same request again: answer, do not redo.
  if (stepping_ && stepping_->client_id() == q.client_id() &&
      stepping_->sequence_number() == q.sequence_number()) {
    return;  // still stepping for it: the reply comes when the steps are done
  }
  if (auto last = last_reply_.find(q.client_id());
      last != last_reply_.end() && last->second.sequence_number() == q.sequence_number()) {
    replies_.write(last->second);
    return;
  }
  switch (q.command()) {
    case mm::SIM_PAUSE:
      control_.paused = true;
      break;
    case mm::SIM_RUN:
      control_.paused = false;
      break;
    case mm::SIM_SET_RTF:
      if (!std::isfinite(q.real_time_factor()) || q.real_time_factor() < 0) {
        replies_.write(reply_to(q, mm::ERR_INVALID_ARGUMENT, "real_time_factor must be >= 0"));
        return;
      }
      control_.real_time_factor = q.real_time_factor();
      break;
    case mm::SIM_STEP:
      if (stepping_) {
        replies_.write(reply_to(q, mm::ERR_INVALID_ARGUMENT, "a step request is still running"));
        return;
      }
      if (q.steps() == 0) break;  // zero steps: answered at once
      control_.pending_steps = q.steps();
      stepping_ = q;
      return;  // answered by after_publish()
    case mm::SIM_LOAD_WORLD:
      try {
        WorldSpec spec = load_world_file(q.world_file());
        std::vector<std::string> old_robots, new_robots;
        for (const auto& r : simulation_.world().robots()) old_robots.push_back(r->name());
        for (const auto& r : spec.robots) new_robots.push_back(r.name);
        if (old_robots != new_robots) {
          replies_.write(reply_to(q, mm::ERR_INVALID_ARGUMENT,
                                  "the new world must have the same robots (names) as this one"));
          return;
        }
        simulation_.load(std::move(spec));  // publishers restart their schedules by themselves
      } catch (const WorldFileError& e) {
        replies_.write(reply_to(q, mm::ERR_BAD_FILE, e.what()));
        return;
      }
      break;
    case mm::SIM_FEATURES:
    case mm::SIM_STATUS:
      break;
    default:
      replies_.write(reply_to(q, mm::ERR_UNKNOWN_OPERATION,
                              "unknown simulation command " + std::to_string(q.command())));
      return;
  }
  send(reply_to(q, mm::ERR_OK, ""));
}

void SimulationServer::send(const Reply& reply) {
  last_reply_[reply.client_id()] = reply;
  replies_.write(reply);
}

void SimulationServer::after_publish() {
  if (!stepping_ || control_.pending_steps == 0) return;
  if (--control_.pending_steps == 0) {
    send(reply_to(*stepping_, mm::ERR_OK, ""));
    stepping_.reset();
  }
}

}  // namespace macsim
