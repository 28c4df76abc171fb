// Calls over a request/reply topic pair correlated in the payload (client id + sequence
// number), so any DDS implementation can serve or call them.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include "macsim/client/commands_sent.h"
#include "macsim/dds/log.h"
#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgs.h"

namespace macsim::client {

/// How a call ended, and why there was no reply when there was none.
struct CallOutcome {
  enum class Kind {
    Replied,      ///< the final reply came
    NoServer,     ///< no server was matched within the timeout
    Busy,         ///< the server acknowledged the request and was still working on it
    Gone,         ///< a server was matched (or acknowledged) and then stopped answering
    Interrupted,  ///< the call was told to give up
  };
  Kind kind = Kind::Replied;
  bool acknowledged = false;  ///< a progress reply (ERR_IN_PROGRESS) came for the request
  bool unmatched = false;     ///< Gone: the server's reader or writer went away
  std::string progress;       ///< the last progress reply's message
  uint64_t steps_done = 0;    ///< the last progress of a step request: its steps done
  uint64_t steps_asked = 0;   ///< and the steps it asked for (0: no step request)
  double waited = 0;          ///< s the call waited
  double since_heard = 0;     ///< s since the server was last heard of (acknowledged: progress)
};

/// A time the server was gone (killed, restarting) during a call and came back.
struct Gap {
  double seconds = 0;            ///< s from its going to the first reply after it came back
  std::optional<uint64_t> step;  ///< the simulator's step count in that reply, if it says
};

/// `n` with thousands separated by commas: 2,147,483,648.
inline std::string with_commas(uint64_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

/// One sentence saying why a call of `service` (e.g. "simulation control") got no reply; the
/// domain is named when `domain` >= 0.
inline std::string describe(const CallOutcome& o, const std::string& service, int domain = -1) {
  const auto seconds = [](double s) {
    std::string text = std::to_string(static_cast<long long>(s * 10 + 0.5) / 10);
    const long long tenth = static_cast<long long>(s * 10 + 0.5) % 10;
    return tenth ? text + "." + std::to_string(tenth) : text;
  };
  const std::string on = domain >= 0 ? " on DDS domain " + std::to_string(domain) : "";
  switch (o.kind) {
    case CallOutcome::Kind::Replied:
      return "the simulator answered the " + service;
    case CallOutcome::Kind::NoServer:
      return "no simulator answered the " + service + on + " within " + seconds(o.waited) +
             " s: is macsim running with the same --domain and DDS profile?";
    case CallOutcome::Kind::Busy:
      if (!o.acknowledged) {
        return "the simulator did not answer this " + service + " request within " +
               seconds(o.waited) + " s (too short to hear its progress); pass a longer timeout";
      }
      if (o.steps_asked > 0) {
        return "the simulator is busy with this request: " + with_commas(o.steps_done) + " of " +
               with_commas(o.steps_asked) + " steps done after " + seconds(o.waited) +
               " s; pass a longer timeout or cancel it";
      }
      return "the simulator is busy with this request: " + o.progress + "; pass a longer timeout";
    case CallOutcome::Kind::Gone:
      if (o.acknowledged) {
        return "the simulator acknowledged this " + service + " request" + on +
               " and stopped answering " + seconds(o.since_heard) + " s ago (" +
               (o.unmatched ? "its participant left: killed or stopped?" : "killed or hung?") + ")";
      }
      return "a simulator" + on + " was found but " +
             (o.unmatched ? "left before answering this " + service + " request"
                          : "did not answer this " + service + " request in " +
                                seconds(o.waited) + " s (hung, or a version without progress "
                                "replies?)");
    case CallOutcome::Kind::Interrupted:
      return "the " + service + " call was interrupted";
  }
  return {};
}

/// Sends requests with this client's id and the next sequence number, waits for the reply that
/// echoes both; resends after every second without a word from the server, acknowledged or not
/// (servers answer a repeat without redoing: with its progress, or the reply sent before).
/// Replies with code ERR_IN_PROGRESS are progress, never the final reply. Calls may run on
/// several threads at once (e.g. one waits on a step, another cancels it).
template <class RequestPubSub, class ReplyPubSub>
class RequestReply {
 public:
  using Request = typename RequestPubSub::type;
  using Reply = typename ReplyPubSub::type;

  /// A request not heard of this long is sent again (a lost reply or progress is answered).
  static constexpr std::chrono::milliseconds kResend{1000};
  /// An acknowledged request whose server is silent this long, though still matched, is given
  /// up as gone (hung). A killed server is unmatched sooner, when its participant's lease (5 s
  /// in the shipped profiles) runs out. 2.5 s here was met by a live simulator starved of the
  /// CPU by a loaded machine (a test failed so).
  static constexpr std::chrono::milliseconds kSilence{6000};
  /// The servers' progress period, and the reliable writers' heartbeat period of the DDS
  /// profiles (a lost sample is repaired within about one): silence must last several of each.
  static constexpr std::chrono::milliseconds kProgressPeriod{300};
  static constexpr std::chrono::milliseconds kHeartbeatPeriod{100};
  static_assert(kSilence >= 2 * kResend, "a silent server gets two resends before it is gone");
  static_assert(kSilence >= 5 * kProgressPeriod && kSilence >= 10 * kHeartbeatPeriod,
                "one lost progress reply must not look like a server gone");

  RequestReply(dds::Participant& participant, const std::string& request_topic,
               const std::string& reply_topic, std::string client_id)
      : client_id_(client_id.empty() ? unique_client_id() : std::move(client_id)),
        domain_(participant.domain()),
        requests_(participant, request_topic, dds::QosFamily::Request),
        replies_(participant, reply_topic, dds::QosFamily::Request,
                 typename dds::Reader<ReplyPubSub>::SentCallback(
                     [this](const Reply& r, const dds::SampleId& id) { heard(r, id); })) {}

  /// Asked at least every 100 ms while a call waits: true gives up at once (a Ctrl-C).
  using Interrupted = std::function<bool()>;

  /// A server that goes away during a call (killed, restarting: macsim --resume; or a network
  /// partition longer than the participants' lease) is waited
  /// for up to `patience`, then the same request is sent again (a resumed simulator answers
  /// what it answered before, finishes a step request it had begun, runs nothing twice);
  /// `before_resend` runs first (e.g. to send the set-points again). Each such gap is said on
  /// stderr and kept (gaps()). 0, the default: the call ends, Gone. Before any call.
  void set_restart_patience(std::chrono::milliseconds patience,
                            std::function<void()> before_resend = {}) {
    patience_ = patience;
    before_resend_ = std::move(before_resend);
  }
  /// The gaps calls rode out so far, oldest first.
  std::vector<Gap> gaps() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return gaps_;
  }

  /// Sends `request` and waits for its reply; nullopt if none came within `timeout` (or
  /// `interrupted` said so, or the server stopped answering); `outcome` (and last_outcome())
  /// then says why.
  std::optional<Reply> call(Request request,
                            std::chrono::milliseconds timeout = std::chrono::seconds(10),
                            const Interrupted& interrupted = {}, CallOutcome* outcome = nullptr) {
    const auto start = Clock::now();
    auto deadline = start + timeout;
    CallOutcome result;
    const auto finish = [&](CallOutcome::Kind kind) {
      result.kind = kind;
      result.waited = seconds(Clock::now() - start);
      std::lock_guard<std::mutex> lock(mutex_);
      last_outcome_ = result;
      if (outcome) *outcome = result;
    };
    bool stopped = false;
    const Interrupted watched = [&] { return stopped = interrupted && interrupted(); };
    // The server that answered the last call is gone (killed, restarting), or another came
    // (restarted before the old one's lease ran out): a gap from here.
    std::optional<Clock::time_point> gone;
    bool new_server_prepared = false;  // what precedes a request to a new server went (below)
    if (patience_ > std::chrono::milliseconds::zero() && served_.load() &&
        (requests_.matched() == 0 || replies_.matched() == 0 ||
         requests_.matched_ever() != served_by_.load())) {
      gone = start;
      say_gone();
    }
    if (!wait_for_server(std::max(timeout, patience_), watched)) {
      finish(stopped ? CallOutcome::Kind::Interrupted : CallOutcome::Kind::NoServer);
      return std::nullopt;
    }
    if (gone) {
      if (before_resend_) before_resend_();
      new_server_prepared = true;
      deadline = Clock::now() + timeout;  // the call's time starts once the server is back
    }
    request.client_id(client_id_);
    // What this participant's robot commands were: none acts after a request that puts the
    // world back, whenever DDS delivers it; a step request steps on them.
    if constexpr (requires { request.commands_sent(); }) {
      if (names_commands_sent(request)) request.commands_sent(commands_sent(domain_));
    }
    std::unique_lock<std::mutex> lock(mutex_);
    const uint64_t sequence = next_sequence_++;
    request.sequence_number(sequence);
    Pending& pending = pending_[sequence];
    pending.heard = Clock::now();
    struct Forget {  // the pending entry goes however the call ends
      RequestReply* self;
      uint64_t sequence;
      ~Forget() { self->pending_.erase(sequence); }  // under mutex_: destroyed before `lock`
    };
    std::optional<Reply> reply;
    auto resend = Clock::now();
    auto awake = resend;  // when this loop last ran
    CallOutcome::Kind kind = CallOutcome::Kind::Replied;
    {
      const Forget forget{this, sequence};
      while (true) {
        const auto now = Clock::now();
        // This thread did not run for a while (a machine short of cores): the threads that
        // hear the server did not either, so that time is not the server's silence.
        if (now - awake > kStall) pending.heard += (now - awake) - kSlice;
        awake = now;
        if (pending.reply) {
          reply = std::move(pending.reply);
          // Another server than the last one answered: the last one went away between calls
          // (killed, and restarted before this client saw it go).
          if (!gone && patience_ > std::chrono::milliseconds::zero() && server_ &&
              pending.server != *server_)
            gone = last_served_;
          if (gone) came_back(*gone, *reply);
          served_by_.store(requests_.matched_ever());
          server_ = pending.server;
          last_served_ = Clock::now();
          break;
        }
        if (now >= deadline) {
          // Silent for long without a progress reply: hung, or a server without them.
          kind = pending.acknowledged || now - pending.heard < kSilence ? CallOutcome::Kind::Busy
                                                                        : CallOutcome::Kind::Gone;
          break;
        }
        if (pending.acknowledged && now - pending.heard > kSilence) {
          if (!ride_out(gone, now, deadline, pending)) {
            kind = CallOutcome::Kind::Gone;
            break;
          }
        }
        // Unacknowledged, or acknowledged and silent for a second (a progress or the final
        // reply lost, or overwritten in the reply writer's history): sent again; the server
        // answers the repeat with its progress or its reply, and never runs it twice.
        if (now >= resend && (!pending.acknowledged || now - pending.heard >= kResend)) {
          // A server matched since the last reply (restarted while the old one still looks
          // matched): a gap; what must precede the request goes first.
          const bool new_server = patience_ > std::chrono::milliseconds::zero() && served_.load() &&
                                  !new_server_prepared &&
                                  requests_.matched_ever() != served_by_.load();
          if (new_server) {
            new_server_prepared = true;
            if (!gone) {
              gone = now;
              say_gone();
            }
          }
          lock.unlock();
          if (new_server) {
            if (before_resend_) before_resend_();
            deadline = std::max(deadline, Clock::now() + timeout);
          }
          requests_.write(request);
          lock.lock();
          resend = Clock::now() + kResend;
          continue;
        }
        replied_.wait_until(lock, std::min(deadline, now + kSlice));
        if (pending.reply) continue;
        lock.unlock();
        const bool stop = interrupted && interrupted();
        const bool unmatched = requests_.matched() == 0 || replies_.matched() == 0;
        lock.lock();
        if (stop) {
          kind = CallOutcome::Kind::Interrupted;
          break;
        }
        if (unmatched && !pending.reply) {
          if (ride_out(gone, Clock::now(), deadline, pending)) {
            // Back once matched both ways: the same request again, at once.
            lock.unlock();
            const bool back = wait_for_server(kSlice, interrupted);
            if (back && before_resend_) before_resend_();
            lock.lock();
            if (back) resend = Clock::now();
            continue;
          }
          result.unmatched = true;
          kind = CallOutcome::Kind::Gone;
          break;
        }
      }
      result.acknowledged = pending.acknowledged;
      result.progress = pending.progress;
      result.steps_done = pending.steps_done;
      result.steps_asked = pending.steps_asked;
      result.since_heard = seconds(Clock::now() - pending.heard);
    }
    lock.unlock();
    finish(kind);
    return reply;
  }

  /// Waits until a server is matched both ways.
  bool wait_for_server(std::chrono::milliseconds timeout, const Interrupted& interrupted = {}) {
    const auto deadline = Clock::now() + timeout;
    for (int polls = 1; requests_.matched() == 0 || replies_.matched() == 0; ++polls) {
      if (Clock::now() > deadline) return false;
      if (interrupted && polls % 5 == 0 && interrupted()) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }

  /// How the last call that ended (on any thread) ended.
  CallOutcome last_outcome() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_outcome_;
  }

  const std::string& client_id() const { return client_id_; }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds kSlice{100};
  /// A wait of kSlice that took this long or longer is this process's stall, not the server's.
  static constexpr std::chrono::milliseconds kStall{500};
  struct Pending {
    std::optional<Reply> reply;
    bool acknowledged = false;
    Clock::time_point heard;  // the last progress, or the call's start
    std::string progress;
    uint64_t steps_done = 0;
    uint64_t steps_asked = 0;
    std::array<uint8_t, 16> server{};  // the writer of the reply
  };

  static double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

  /// An id no other client shares, also not a later one of this process at the same address or
  /// one of a later process with the same pid: servers keep replies by id and sequence number.
  static std::string unique_client_id() {
    static std::atomic<uint64_t> made{0};
    static const uint64_t salt = [] {
      std::random_device random;
      return (uint64_t{random()} << 32) ^ random() ^
             static_cast<uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
    }();
    char tag[17];
    std::snprintf(tag, sizeof tag, "%016llx", static_cast<unsigned long long>(salt));
    return "client-" + std::to_string(::getpid()) + "-" + std::to_string(++made) + "-" + tag;
  }

  /// A call's server is gone (unmatched, or silent too long): true while the patience lasts
  /// (the call's deadline moved on by the time waited), said once on stderr. Under mutex_.
  bool ride_out(std::optional<Clock::time_point>& gone, Clock::time_point now,
                Clock::time_point& deadline, Pending& pending) {
    if (patience_ <= std::chrono::milliseconds::zero()) return false;
    if (!gone) {
      gone = now;
      deadline += patience_;
      say_gone();
    }
    pending.heard = now;  // its silence starts again once it is back
    return now - *gone <= patience_;
  }

  void say_gone() const {
    log::warn(
        "macsim client: the server of {} went away (killed, restarting, or the network cut?); "
        "waiting up to {:.0f} s for it to come back",
        requests_.topic_name(), seconds(patience_));
  }

  /// The first reply after a gap: said, and kept. Under mutex_.
  void came_back(Clock::time_point gone, const Reply& reply) {
    Gap gap;
    gap.seconds = seconds(Clock::now() - gone);
    if constexpr (requires { reply.steps(); }) gap.step = reply.steps();
    gaps_.push_back(gap);
    log::info("macsim client: the server of {} is back after {:.1f} s{}", requests_.topic_name(),
              gap.seconds, gap.step ? " at step " + std::to_string(*gap.step) : std::string());
  }

  /// On Fast DDS's thread: a reply or progress of one of this client's calls.
  void heard(const Reply& r, const dds::SampleId& id) {
    if (r.client_id() != client_id_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto pending = pending_.find(r.sequence_number());
    if (pending == pending_.end()) return;
    Pending& p = pending->second;
    if (r.code() == macsim_msgs::msg::dds_::ERR_IN_PROGRESS) {
      p.acknowledged = true;
      p.heard = Clock::now();
      p.progress = r.message();
      if constexpr (requires { r.steps_done(); r.steps_asked(); }) {
        p.steps_done = r.steps_done();
        p.steps_asked = r.steps_asked();
      }
    } else {
      p.reply = r;
      p.server = id.writer;
      served_.store(true);
    }
    replied_.notify_all();
  }

  std::string client_id_;
  mutable std::mutex mutex_;
  uint64_t next_sequence_ = 1;
  std::map<uint64_t, Pending> pending_;  // by sequence number: the calls waiting
  CallOutcome last_outcome_;
  std::chrono::milliseconds patience_{0};
  std::function<void()> before_resend_;
  std::vector<Gap> gaps_;
  std::atomic<bool> served_{false};  // a final reply came (a server answered this client)
  std::atomic<int> served_by_{0};    // requests_.matched_ever() when the last reply came
  std::optional<std::array<uint8_t, 16>> server_;  // the last reply's writer (under mutex_)
  Clock::time_point last_served_;                  // when it came (under mutex_)
  std::condition_variable replied_;
  int domain_;  // its requests name the process's robot commands on this domain
  dds::Writer<RequestPubSub> requests_;
  dds::Reader<ReplyPubSub> replies_;
};

}  // namespace macsim::client
