#include "simulation/simulation_server.h"

#include <algorithm>

#include "macsim/dds/log.h"
#include "macsim/dds/topics.h"
#include "macsim/dds/wire.h"
#include "macsim/sim_core/world_loader.h"
#include "simulation/simulation_dispatch.h"
#include "supervisor/supervisor_codec.h"
#include "typed_request.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

namespace {

using SimPubSub = mm::SimulationRequest_PubSubType;
/// A simulation request run on the simulation thread (a step, a pause, a reset, ...).
using SimulationCall = TypedRequest<SimPubSub>;
/// A world load sent again: answered as the first was, never loaded twice.
using RepeatedLoad = TypedRequest<SimPubSub, struct RepeatedLoadKind>;
/// A world load sent while another still runs: refused.
using LoadWhileLoading = TypedRequest<SimPubSub, struct LoadWhileLoadingKind>;

/// The request as a command of type R (named by its command code).
template <class R>
Command simulation_command(const mm::SimulationRequest_& r, const char* name) {
  return request_command<R>(CommandSource::Simulation, r,
                            name ? std::string(name) : "SIM_" + std::to_string(r.command()));
}

/// What a request waits for before the simulation thread takes it.
std::string waiting_text(const mm::SimulationRequest_& r) {
  if (r.command() == mm::SIM_LOAD_WORLD) return "loading the world '" + r.world_file() + "'";
  return "waiting for the simulation thread (a step or a world load before it)";
}

}  // namespace

SimulationServer::SimulationServer(dds::Participant& participant, Runner& runner, LoadLimits limits,
                                   LatestReadings readings, HeldOutput held)
    : runner_(runner),
      limits_(limits),
      readings_(std::move(readings)),
      held_(std::move(held)),
      progress_([this](const Reply& reply) { service_.reply(reply); }) {
  // On the simulation thread: control of the run, not of the world (a load is recorded by the
  // runner when the new world is swapped in).
  runner_.set_executor<SimulationCall>(
      [this](const SimulationCall& call, const Command& c, World&) {
        const Request& r = call.message();
        if (auto resumed = resumable_.extract({r.client_id(), r.sequence_number()})) {
          execute(resumed.mapped());  // begun before a kill: on to the end it asked for
        } else if (repeated(r)) {
          runner_.answered_repeat(c);
        } else {
          execute(r);
        }
        return false;
      });
  runner_.set_executor<RepeatedLoad>([this](const RepeatedLoad& call, const Command& c, World&) {
    progress_.end(call.message().client_id(), call.message().sequence_number());
    repeated(call.message());
    runner_.answered_repeat(c);
    return false;
  });
  runner_.set_executor<LoadWhileLoading>(
      [this](const LoadWhileLoading& call, const Command&, World&) {
        send(reply_to(call.message(), mm::ERR_INVALID_ARGUMENT, "a world load is still running"));
        return false;
      });
  // On Fast DDS's thread: queue the request; it runs on the simulation thread. A load is queued
  // as a load, so that its file is parsed at once, off the simulation thread. A repeat of a
  // request still running gets its progress (RequestProgress) and is not queued again.
  service_.open(participant, {dds::topics::kSimulationRequest, dds::topics::kSimulationReply},
                [this](const Request& r, const dds::RequestId&) {
                  const auto asked = [steps = r.command() == mm::SIM_STEP ? r.steps() : 0](
                                         Reply& p) { p.steps_asked(steps); };
                  if (!progress_.begin(r, waiting_text(r), asked)) return;
                  if (r.command() != mm::SIM_LOAD_WORLD) {
                    if (!runner_.push(simulation_command<SimulationCall>(r, nullptr)))
                      refuse_full(r);
                    return;
                  }
                  if (load_seen(r)) {
                    // Sent again: never load twice; answer again if the load was answered.
                    const bool pushed =
                        runner_.push(simulation_command<RepeatedLoad>(r, "answer_repeated_load"));
                    if (!pushed) refuse_full(r);
                    return;
                  }
                  const LoadQueued queued = queue_world_load(
                      runner_, limits_, {r.world_file(), ""},
                      [this, r](const LoadOutcome& outcome) {
                        send(reply_to(r, codec::error_code(outcome.code), outcome.error));
                      },
                      codec::senders(r.commands_sent()));
                  if (queued == LoadQueued::QueueFull) {
                    forget_load(r);  // not loaded: a repeat may try again
                    refuse_full(r);
                  } else if (queued == LoadQueued::LoadRunning) {
                    const bool pushed = runner_.push(
                        simulation_command<LoadWhileLoading>(r, "answer_load_running"));
                    if (!pushed) refuse_full(r);
                  }
                });
}

void SimulationServer::refuse_full(const Request& q) {
  Reply reply;  // nothing of the runner: it belongs to the simulation thread
  reply.client_id(q.client_id());
  reply.sequence_number(q.sequence_number());
  reply.code(mm::ERR_LIMIT_REACHED);
  reply.message(runner_.queue_full_message());
  progress_.end(q.client_id(), q.sequence_number());
  service_.reply(reply);
}

bool SimulationServer::load_seen(const Request& r) {
  std::lock_guard<std::mutex> lock(loads_mutex_);
  const uint64_t use = ++load_uses_;
  auto seen = loads_seen_.find(r.client_id());
  if (seen == loads_seen_.end()) {
    if (loads_seen_.size() >= kMaxLoadClients) {
      const auto oldest = std::min_element(
          loads_seen_.begin(), loads_seen_.end(),
          [](const auto& a, const auto& b) { return a.second.use < b.second.use; });
      loads_seen_.erase(oldest);
    }
    seen = loads_seen_.emplace(r.client_id(), LoadsSeen{}).first;
  }
  LoadsSeen& loads = seen->second;
  loads.use = use;
  const uint64_t sequence = r.sequence_number();
  if (loads.recent.count(sequence) || sequence <= loads.forgotten_through) return true;
  loads.recent.insert(sequence);
  if (loads.recent.size() > kLoadWindow) {
    loads.forgotten_through = std::max(loads.forgotten_through, *loads.recent.begin());
    loads.recent.erase(loads.recent.begin());
  }
  return false;
}

void SimulationServer::remember_load(const std::string& client_id, uint64_t sequence_number) {
  Request r;
  r.client_id(client_id);
  r.sequence_number(sequence_number);
  (void)load_seen(r);
}

void SimulationServer::forget_load(const Request& r) {
  std::lock_guard<std::mutex> lock(loads_mutex_);
  if (auto seen = loads_seen_.find(r.client_id()); seen != loads_seen_.end()) {
    seen->second.recent.erase(r.sequence_number());
  }
}

SimulationServer::~SimulationServer() {
  service_.close();
  // What is still queued runs nowhere.
  runner_.set_executor<SimulationCall>({});
  runner_.set_executor<RepeatedLoad>({});
  runner_.set_executor<LoadWhileLoading>({});
}

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
    progress_.end(q.client_id(), q.sequence_number());
    service_.reply(*again);
    return true;
  }
  if (replied_.forgotten(q)) {  // answered long ago: its reply is gone, it must not run again
    progress_.end(q.client_id(), q.sequence_number());
    service_.reply(
        reply_to(q, mm::ERR_LIMIT_REACHED, replied_.forgotten_message(q.sequence_number())));
    return true;
  }
  return false;
}

void SimulationServer::execute(const Request& q) {
  if (q.command() == mm::SIM_CANCEL) {
    send(cancel(q));
    return;
  }
  auto steps_done = std::make_shared<std::atomic<uint64_t>>(0);
  auto reply = dispatch_simulation(
      q, runner_,
      [this, at_end = bool(q.step_options() & mm::STEP_PUBLISH_AT_END)](Reply stepped) {
        stepping_.reset();
        // What its end wrote (the request_end hook ran before this): a reader waits for those.
        // (A request refused before its first step wrote nothing.)
        if (at_end && stepped.code() != mm::ERR_COMMANDS_MISSING) stepped.published(published());
        if (!cancelling_) {
          send(stepped);
          return;
        }
        Reply cancelled = stepped;
        cancelled.message("cancelled by its client (SIM_CANCEL) after " +
                          std::to_string(stepped.steps_done()) + " of " +
                          std::to_string(stepped.steps_asked()) + " steps");
        cancelled_ = cancelled;
        send(cancelled);
      },
      readings_, steps_done,
      [this, q] {
        // Taken, as it stands after its first step (the robot commands sent before it are
        // written before this): a resumed simulator finishes it.
        Request left = q;
        left.steps(q.steps() - 1);
        runner_.record_request({runner_.steps_run(), RecordedRequest::Kind::Taken, kSessionService,
                                dds::to_wire<mm::SimulationRequest_PubSubType>(left)});
      });
  if (reply) {
    if (q.command() == mm::SIM_STEP && q.steps() == 0 && reply->code() == mm::ERR_OK &&
        (q.step_options() & mm::STEP_PUBLISH_AT_END) && held_.flush) {
      // No step to take (a resumed request whose steps all ran before the kill): what they
      // kept back goes out now, before its reply.
      held_.flush();
      reply->published(published());
    }
    send(*reply, q.command() == mm::SIM_STATUS || q.command() == mm::SIM_FEATURES);
    return;
  }
  stepping_ = q;
  progress_.update(q.client_id(), q.sequence_number(),
                   "stepping " + std::to_string(q.steps()) + " steps",
                   [steps_done, asked = q.steps()](Reply& progress) {
                     progress.steps_done(steps_done->load(std::memory_order_relaxed));
                     progress.steps_asked(asked);
                   });
}

std::vector<std::string> SimulationServer::published() const {
  if (!held_.published) return {};
  std::vector<std::string> topics = held_.published();
  if (topics.size() > 64) topics.resize(64);  // the field's bound (macsim_msgs.idl)
  return topics;
}

SimulationServer::Reply SimulationServer::cancel(const Request& q) {
  const uint64_t named = q.cancel_sequence_number();
  if (!stepping_ || stepping_->client_id() != q.client_id() ||
      (named != 0 && stepping_->sequence_number() != named)) {
    return reply_to(q, mm::ERR_NOT_APPLICABLE,
                    named == 0 ? "no step request of this client is running"
                               : "request " + std::to_string(named) +
                                     " of this client is no step request running");
  }
  const uint64_t ended = stepping_->sequence_number();
  // A pause cancels the request; the simulation then goes on as it did.
  const bool paused = runner_.settings().paused;
  cancelling_ = true;
  runner_.pause();
  cancelling_ = false;
  if (!paused) runner_.resume();
  Reply reply = reply_to(q, mm::ERR_OK, "");
  if (cancelled_) {
    reply.message("cancelled request " + std::to_string(ended) + " after " +
                  std::to_string(cancelled_->steps_done()) + " of " +
                  std::to_string(cancelled_->steps_asked()) + " steps");
    reply.steps_done(cancelled_->steps_done());
    reply.steps_asked(cancelled_->steps_asked());
    reply.ended_by(mm::STEP_CANCELLED);
    cancelled_.reset();
  }
  return reply;
}

void SimulationServer::send(const Reply& reply, bool query) {
  progress_.end(reply.client_id(), reply.sequence_number());
  replied_.remember(reply);
  // On disk before it goes out: a repeat after a resume gets it again, and runs nothing.
  if (!query) {
    runner_.record_request({runner_.steps_run(), RecordedRequest::Kind::Answered, kSessionService,
                            dds::to_wire<mm::SimulationReply_PubSubType>(reply)});
  }
  service_.reply(reply);
}

std::vector<SimulationServer::Begun> SimulationServer::begun(
    const std::vector<RecordedRequest>& requests) {
  // By client and sequence number: the request taken, in the order taken.
  std::map<std::pair<std::string, uint64_t>, std::size_t> taken;
  std::vector<std::optional<Begun>> in_order;
  for (const auto& recorded : requests) {
    if (recorded.service != kSessionService) continue;
    if (recorded.kind == RecordedRequest::Kind::Taken) {
      if (const auto q = dds::from_wire<mm::SimulationRequest_PubSubType>(recorded.bytes)) {
        // Taken again (a resumed run going on with it): the one taken last is the one begun.
        auto [t, added] = taken.try_emplace({q->client_id(), q->sequence_number()}, 0);
        uint64_t first = recorded.step;
        if (!added && in_order[t->second]) {
          first = in_order[t->second]->first_step;
          in_order[t->second].reset();
        }
        t->second = in_order.size();
        in_order.push_back(Begun{recorded.step, first, *q});
      }
    } else if (const auto reply = dds::from_wire<mm::SimulationReply_PubSubType>(recorded.bytes)) {
      if (auto t = taken.find({reply->client_id(), reply->sequence_number()}); t != taken.end())
        in_order[t->second].reset();  // answered
    }
  }
  std::vector<Begun> out;
  for (auto& each : in_order) {
    if (each) out.push_back(std::move(*each));
  }
  return out;
}

void SimulationServer::resume(const std::vector<RecordedRequest>& requests) {
  std::optional<Reply> last;
  for (const auto& recorded : requests) {
    if (recorded.service != kSessionService || recorded.kind == RecordedRequest::Kind::Taken)
      continue;
    const auto reply = dds::from_wire<mm::SimulationReply_PubSubType>(recorded.bytes);
    if (!reply) continue;
    replied_.remember(*reply);
    remember_load(reply->client_id(), reply->sequence_number());
    last = reply;
  }
  if (last) {  // the run as its last answer left it
    if (last->paused()) {
      runner_.pause();
    } else {
      runner_.resume();
    }
    (void)runner_.set_real_time_factor(last->real_time_factor());
  }
  for (Begun& each : begun(requests)) {
    const uint64_t step = each.step;
    Request& q = each.request;
    // Its steps ran and its reply was lost with the process: a repeat is answered at once.
    const uint64_t done = std::min<uint64_t>(runner_.steps_run() - step, q.steps());
    log::info(
        "macsim: step request {} of client {}, taken at step {}, goes on from step {} when "
        "its client sends it again ({} of its {} steps left)",
        q.sequence_number(), q.client_id(), step, runner_.steps_run(), q.steps() - done, q.steps());
    q.steps(q.steps() - done);
    // What it named went to the killed process (the commands took effect there, or come from
    // the session now): this one never hears them.
    q.commands_sent({});
    remember_load(q.client_id(), q.sequence_number());
    // Not at once: its data would go out before the client's readers have found this process.
    resumable_[{q.client_id(), q.sequence_number()}] = q;
    // With the set-points it had: its client, not knowing it was begun, sends them again
    // before the repeat, and they must not act in its middle (the first step drops them).
    if (q.steps() > 0) runner_.drop_robot_commands_until_next_step();
  }
}

}  // namespace macsim
