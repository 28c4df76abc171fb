#include "simulation_server.h"

#include "macsim/dds/topics.h"
#include "macsim/sim_core/world_loader.h"
#include "supervisor_codec.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

SimulationServer::SimulationServer(dds::Participant& participant, Runner& runner, LoadLimits limits)
    : runner_(runner),
      limits_(limits),
      replies_(participant, dds::topics::kSimulationReply, dds::QosFamily::Command) {
  // On Fast DDS's thread: queue the request; it runs on the simulation thread. A load is queued
  // as a load, so that its file is parsed at once, off the simulation thread.
  requests_ = std::make_unique<dds::Reader<mm::SimulationRequest_PubSubType>>(
      participant, dds::topics::kSimulationRequest, dds::QosFamily::Command,
      [this](const Request& r) {
        if (r.command() != mm::SIM_LOAD_WORLD) {
          runner_.push([this, r](World&) { execute(r); });
          return;
        }
        {
          std::lock_guard<std::mutex> lock(loads_mutex_);
          auto [last, fresh] = last_load_.try_emplace(r.client_id(), r.sequence_number());
          if (!fresh && last->second == r.sequence_number()) {
            // Sent again: never load twice; answer again once the first load is answered.
            runner_.push([this, r](World&) { repeated(r); });
            return;
          }
          last->second = r.sequence_number();
        }
        const bool queued = runner_.load(
            [file = r.world_file(), this] {
              LoadOptions options;
              options.limits = limits_;
              return load_world_file(file, options);
            },
            [this, r](const LoadOutcome& outcome) {
              send(reply_to(r, codec::error_code(outcome.code), outcome.error));
            });
        if (!queued) {
          runner_.push([this, r](World&) {
            send(reply_to(r, mm::ERR_INVALID_ARGUMENT, "a world load is still running"));
          });
        }
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
  const World& world = runner_.world();
  r.sim_time(world.time());
  r.steps(world.steps());
  r.state_hash(world.state_hash());
  r.paused(runner_.settings().paused);
  r.real_time_factor(runner_.settings().real_time_factor);
  r.features(
      "simulator,supervisor,lockstep,ground_truth,reset,snapshot,load_world,cameras,laser,crane");
  return r;
}

bool SimulationServer::repeated(const Request& q) {
  // A client that did not hear its reply sends the same request again: answer, do not redo.
  if (stepping_ && stepping_->client_id() == q.client_id() &&
      stepping_->sequence_number() == q.sequence_number()) {
    return true;  // still stepping for it: the reply comes when the steps are done
  }
  if (const Reply* again = replied_.find(q)) {
    replies_.write(*again);
    return true;
  }
  return false;
}

void SimulationServer::execute(const Request& q) {
  if (repeated(q)) return;
  switch (q.command()) {
    case mm::SIM_PAUSE:
      runner_.pause();
      break;
    case mm::SIM_RUN:
      runner_.resume();
      break;
    case mm::SIM_SET_RTF:
      if (!runner_.set_real_time_factor(q.real_time_factor())) {
        send(reply_to(q, mm::ERR_INVALID_ARGUMENT,
                      "real_time_factor must be 0 (as fast as possible) or at least " +
                          std::to_string(kMinRealTimeFactor)));
        return;
      }
      break;
    case mm::SIM_STEP:
      if (q.steps() == 0) break;  // zero steps: answered at once
      if (!runner_.request_steps(q.steps(), [this, q](bool completed) {
            stepping_.reset();
            send(completed ? reply_to(q, mm::ERR_OK, "")
                           : reply_to(q, mm::ERR_NOT_APPLICABLE, "cancelled by SIM_PAUSE"));
          })) {
        send(reply_to(q, mm::ERR_INVALID_ARGUMENT, "a step request is still running"));
        return;
      }
      stepping_ = q;
      return;  // answered when its last step's data is out
    case mm::SIM_FEATURES:
    case mm::SIM_STATUS:
      break;
    default:
      send(reply_to(q, mm::ERR_UNKNOWN_OPERATION,
                    "unknown simulation command " + std::to_string(q.command())));
      return;
  }
  send(reply_to(q, mm::ERR_OK, ""));
}

void SimulationServer::send(const Reply& reply) {
  replied_.remember(reply);
  replies_.write(reply);
}

}  // namespace macsim
