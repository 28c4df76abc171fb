// The repeated-request check of every request/reply service: a client that did not hear its
// reply sends the same request (same client id and sequence number) again; it gets the same
// reply, and the request is not run twice. One reply per client, for at most `max_clients`
// clients: a client inventing ids pushes out the clients heard from longest ago, not memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

namespace macsim {

/// The last reply sent to each of the clients heard from most recently. `Reply` has
/// client_id() and sequence_number().
template <class Reply>
class ReplyCache {
 public:
  /// Clients whose last reply is kept, by default.
  static constexpr std::size_t kDefaultMaxClients = 1024;

  explicit ReplyCache(std::size_t max_clients = kDefaultMaxClients)
      : max_clients_(max_clients < 1 ? 1 : max_clients) {}

  /// The reply already sent for this request, or nullptr if it is new (or its client's reply
  /// was pushed out by `max_clients` newer clients).
  template <class Request>
  const Reply* find(const Request& request) const {
    const auto last = last_.find(request.client_id());
    if (last == last_.end() || last->second.reply.sequence_number() != request.sequence_number()) {
      return nullptr;
    }
    return &last->second.reply;
  }
  /// Remembers a reply about to be sent; the client heard from longest ago goes when full.
  void remember(const Reply& reply) {
    auto [entry, added] = last_.try_emplace(reply.client_id());
    if (!added) order_.erase(entry->second.tick);
    entry->second = {reply, next_tick_};
    order_.emplace(next_tick_++, entry->first);
    if (last_.size() > max_clients_) {
      last_.erase(order_.begin()->second);
      order_.erase(order_.begin());
    }
  }
  /// Clients whose last reply is kept.
  std::size_t size() const { return last_.size(); }
  std::size_t max_clients() const { return max_clients_; }

 private:
  struct Entry {
    Reply reply;
    uint64_t tick = 0;  // when it was remembered
  };
  std::size_t max_clients_;
  uint64_t next_tick_ = 0;
  std::map<std::string, Entry> last_;
  std::map<uint64_t, std::string> order_;  // tick -> client, oldest first
};

}  // namespace macsim
