// The repeated-request check of every request/reply service: a client that did not hear its
// reply sends the same request (same client id and sequence number) again; it gets the same
// reply, and the request is not run twice.
#pragma once

#include <map>
#include <string>

namespace macsim {

/// The last reply sent to each client. `Reply` has client_id() and sequence_number().
template <class Reply>
class ReplyCache {
 public:
  /// The reply already sent for this request, or nullptr if it is new.
  template <class Request>
  const Reply* find(const Request& request) const {
    const auto last = last_.find(request.client_id());
    if (last == last_.end() || last->second.sequence_number() != request.sequence_number()) {
      return nullptr;
    }
    return &last->second;
  }
  /// Remembers a reply about to be sent.
  void remember(const Reply& reply) { last_[reply.client_id()] = reply; }

 private:
  std::map<std::string, Reply> last_;
};

}  // namespace macsim
