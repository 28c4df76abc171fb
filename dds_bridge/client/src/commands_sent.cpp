#include "macsim/client/commands_sent.h"

#include <algorithm>
#include <map>
#include <mutex>

namespace macsim::client {

namespace mm = macsim_msgs::msg::dds_;

namespace {

/// A request carries at most this many (its IDL bound).
constexpr std::size_t kMaxWriters = 64;

struct Ledger {
  struct Last {
    uint64_t sequence = 0;
    uint64_t noted = 0;  // when, in notes: the writer noted longest ago gives way first
    int domain = -1;     // the DDS domain it writes on
  };
  std::mutex mutex;
  uint64_t notes = 0;
  std::map<std::array<uint8_t, 16>, Last> writers;
};

Ledger& ledger() {
  static Ledger l;
  return l;
}

}  // namespace

void note_command_sent(const dds::SampleId& sent, int domain) {
  Ledger& l = ledger();
  std::lock_guard<std::mutex> lock(l.mutex);
  auto found = l.writers.find(sent.writer);
  if (found == l.writers.end() && l.writers.size() >= kMaxWriters) {
    l.writers.erase(std::min_element(l.writers.begin(), l.writers.end(), [](auto& a, auto& b) {
      return a.second.noted < b.second.noted;
    }));
  }
  Ledger::Last& last = l.writers[sent.writer];
  last.sequence = std::max(last.sequence, sent.sequence);
  last.noted = ++l.notes;
  last.domain = domain;
}

void forget_commands_of(const std::array<uint8_t, 16>& writer) {
  Ledger& l = ledger();
  std::lock_guard<std::mutex> lock(l.mutex);
  l.writers.erase(writer);
}

std::vector<mm::SampleIdentity_> commands_sent(std::optional<int> domain) {
  Ledger& l = ledger();
  std::lock_guard<std::mutex> lock(l.mutex);
  std::vector<mm::SampleIdentity_> sent;
  sent.reserve(l.writers.size());
  for (const auto& [writer, last] : l.writers) {
    if (domain && last.domain != *domain) continue;
    mm::SampleIdentity_ id;
    id.writer_guid(writer);
    id.sequence_number(last.sequence);
    sent.push_back(id);
  }
  return sent;
}

bool puts_world_back(const mm::SupervisorRequest_& request) {
  const int32_t op = request.operation()._d();
  return op == mm::OP_RESET || op == mm::OP_RESTORE_SNAPSHOT;
}

bool puts_world_back(const mm::SimulationRequest_& request) {
  return request.command() == mm::SIM_LOAD_WORLD;
}

bool names_commands_sent(const mm::SupervisorRequest_& request) { return puts_world_back(request); }

bool names_commands_sent(const mm::SimulationRequest_& request) {
  return puts_world_back(request) || request.command() == mm::SIM_STEP;
}

}  // namespace macsim::client
