// The repeated-request check of every request/reply service: a client that did not hear its
// reply sends the same request (same client id and sequence number) again; it gets the same
// reply, and the request is not run twice. Each client's replies to its last `window` requests
// are kept (one client may have several calls in flight), for at most `max_clients` clients and
// `max_bytes` of replies: a client inventing ids or asking for huge replies pushes out the
// clients heard from longest ago, not memory. A repeat older than its client's window is known
// as answered (forgotten()), never run again.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "macsim/msg/macsim_msgs.h"

namespace macsim {

/// A cheap estimate of the bytes a reply holds: its serialized size (strings, sequences) when
/// the type can say it, plus the object itself.
template <class Reply>
std::size_t reply_bytes(const Reply& reply) {
  if constexpr (requires { Reply::getCdrSerializedSize(reply); }) {
    return sizeof(Reply) + Reply::getCdrSerializedSize(reply);
  } else {
    return sizeof(Reply);
  }
}

/// The replies sent to the clients heard from most recently. `Reply` has client_id() and
/// sequence_number(); requests of one client carry increasing sequence numbers.
template <class Reply>
class ReplyCache {
 public:
  /// Clients whose replies are kept, by default.
  static constexpr std::size_t kDefaultMaxClients = 1024;
  /// Replies kept per client (its last requests answered), by default.
  static constexpr std::size_t kDefaultWindow = 16;
  /// Bytes of replies kept in all, by default (reply_bytes()).
  static constexpr std::size_t kDefaultMaxBytes = std::size_t{64} << 20;

  explicit ReplyCache(std::size_t max_clients = kDefaultMaxClients,
                      std::size_t window = kDefaultWindow,
                      std::size_t max_bytes = kDefaultMaxBytes)
      : max_clients_(max_clients < 1 ? 1 : max_clients),
        window_(window < 1 ? 1 : window),
        max_bytes_(max_bytes) {}

  /// The reply already sent for this request, or nullptr if it is new (or its reply is no
  /// longer kept: see forgotten()).
  template <class Request>
  const Reply* find(const Request& request) const {
    const auto client = clients_.find(request.client_id());
    if (client == clients_.end()) return nullptr;
    const auto kept = client->second.replies.find(request.sequence_number());
    return kept == client->second.replies.end() ? nullptr : &kept->second.reply;
  }
  /// True if this request is older than its client's kept replies: it was answered and its
  /// reply is no longer kept (answer it with forgotten_message(), do not run it).
  template <class Request>
  bool forgotten(const Request& request) const {
    const auto client = clients_.find(request.client_id());
    return client != clients_.end() &&
           request.sequence_number() <= client->second.forgotten_through &&
           !client->second.replies.count(request.sequence_number());
  }
  /// What a forgotten request is told (with ERR_LIMIT_REACHED).
  std::string forgotten_message(uint64_t sequence_number) const {
    return "request " + std::to_string(sequence_number) +
           " was already answered; its reply is no longer kept (the replies to a client's last " +
           std::to_string(window_) + " requests are)";
  }
  /// The reply a forgotten request gets: ERR_LIMIT_REACHED with forgotten_message().
  template <class Request>
  Reply forgotten_reply(const Request& request) const {
    Reply reply;
    reply.client_id(request.client_id());
    reply.sequence_number(request.sequence_number());
    reply.code(macsim_msgs::msg::dds_::ERR_LIMIT_REACHED);
    reply.message(forgotten_message(request.sequence_number()));
    return reply;
  }
  /// Remembers a reply about to be sent; beyond the window, the client's oldest reply goes;
  /// beyond the caps, the clients heard from longest ago go.
  void remember(const Reply& reply) {
    auto [client, added] = clients_.try_emplace(reply.client_id());
    Client& c = client->second;
    if (!added) order_.erase(c.tick);
    c.tick = next_tick_++;
    order_.emplace(c.tick, client->first);
    const uint64_t sequence = reply.sequence_number();
    if (auto old = c.replies.find(sequence); old != c.replies.end()) drop(c, old, false);
    const std::size_t size = reply_bytes(reply);
    c.replies.insert_or_assign(sequence, Kept{reply, size, next_tick_++});
    bytes_ += size;
    while (c.replies.size() > window_) drop(c, oldest(c), true);
    if (clients_.size() > max_clients_) forget_client(order_.begin()->second);
    // Over the byte budget: the replies of the clients heard from longest ago go (their ids
    // stay, so that a repeat is still known as answered); never the reply just remembered.
    for (auto o = order_.begin(); bytes_ > max_bytes_ && o != order_.end(); ++o) {
      Client& old = clients_.at(o->second);
      while (bytes_ > max_bytes_ && !old.replies.empty()) {
        const auto victim = oldest(old);
        if (&old == &c && victim->first == sequence) break;
        drop(old, victim, true);
      }
    }
  }
  /// Clients whose replies (or whose answered sequence numbers) are kept.
  std::size_t size() const { return clients_.size(); }
  /// Bytes of the replies kept (reply_bytes()).
  std::size_t bytes() const { return bytes_; }
  std::size_t max_clients() const { return max_clients_; }
  std::size_t window() const { return window_; }
  std::size_t max_bytes() const { return max_bytes_; }

 private:
  struct Kept {
    Reply reply;
    std::size_t bytes = 0;
    uint64_t tick = 0;  // when it was remembered
  };
  struct Client {
    std::map<uint64_t, Kept> replies;  // by sequence number
    uint64_t forgotten_through = 0;    // the highest sequence number whose reply went
    uint64_t tick = 0;                 // when it was last heard from
  };
  using KeptIt = typename std::map<uint64_t, Kept>::iterator;

  static KeptIt oldest(Client& c) {
    auto first = c.replies.begin();
    for (auto r = c.replies.begin(); r != c.replies.end(); ++r) {
      if (r->second.tick < first->second.tick) first = r;
    }
    return first;
  }
  void drop(Client& c, KeptIt r, bool forget) {
    if (forget && r->first > c.forgotten_through) c.forgotten_through = r->first;
    bytes_ -= r->second.bytes;
    c.replies.erase(r);
  }
  void forget_client(const std::string& id) {
    const auto client = clients_.find(id);
    for (const auto& [sequence, kept] : client->second.replies) bytes_ -= kept.bytes;
    order_.erase(client->second.tick);
    clients_.erase(client);
  }

  std::size_t max_clients_;
  std::size_t window_;
  std::size_t max_bytes_;
  std::size_t bytes_ = 0;
  uint64_t next_tick_ = 0;
  std::map<std::string, Client> clients_;
  std::map<uint64_t, std::string> order_;  // tick -> client, heard from longest ago first
};

}  // namespace macsim
