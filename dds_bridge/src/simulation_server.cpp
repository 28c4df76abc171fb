#include "simulation_server.h"

#include "macsim/dds/topics.h"
#include "macsim/sim_core/world_loader.h"
#include "simulation_dispatch.h"
#include "supervisor_codec.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

SimulationServer::SimulationServer(dds::Participant& participant, Runner& runner, LoadLimits limits,
                                   LatestReadings readings)
    : runner_(runner),
      limits_(limits),
      readings_(std::move(readings)),
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
  return simulation_reply(q, runner_, code, message);
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
  auto reply = dispatch_simulation(
      q, runner_,
      [this](const Reply& stepped) {
        stepping_.reset();
        send(stepped);
      },
      readings_);
  if (reply) {
    send(*reply);
  } else {
    stepping_ = q;
  }
}

void SimulationServer::send(const Reply& reply) {
  replied_.remember(reply);
  replies_.write(reply);
}

}  // namespace macsim
