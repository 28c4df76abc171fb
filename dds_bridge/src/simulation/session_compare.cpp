#include "simulation/session_compare.h"

#include <fmt/format.h>

#include <array>
#include <limits>
#include <map>
#include <vector>

#include "macsim/dds/wire.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"

namespace macsim {

namespace {

namespace mm = macsim_msgs::msg::dds_;

/// A run's identities in the order they first appear: a client id or writer becomes its number.
class Identities {
 public:
  std::string client(const std::string& id) {
    const auto [at, _] = clients_.try_emplace(id, clients_.size() + 1);
    return "client " + std::to_string(at->second);
  }
  std::array<uint8_t, 16> writer(const std::array<uint8_t, 16>& guid) {
    const auto [at, _] = writers_.try_emplace(guid, writers_.size() + 1);
    std::array<uint8_t, 16> numbered{};
    const uint64_t n = at->second;
    for (int k = 0; k < 8; ++k) numbered[15 - k] = static_cast<uint8_t>(n >> (8 * k));
    return numbered;
  }

 private:
  std::map<std::string, std::size_t> clients_;
  std::map<std::array<uint8_t, 16>, std::size_t> writers_;
};

template <class Message>
void number_commands_sent(Message& m, Identities& ids) {
  auto sent = m.commands_sent();
  for (auto& s : sent) s.writer_guid(ids.writer(s.writer_guid()));
  m.commands_sent(sent);
}

/// The bytes of a request or reply with its identities numbered (as first seen in this run);
/// bytes of another type as they are.
template <class PubSub, class Number>
std::optional<std::vector<uint8_t>> numbered(const std::vector<uint8_t>& bytes, Number number) {
  auto m = dds::from_wire<PubSub>(bytes);
  if (!m) return std::nullopt;
  number(*m);
  return dds::to_wire<PubSub>(*m);
}

std::vector<uint8_t> numbered_command(const Command& c, Identities& ids) {
  const std::vector<uint8_t> bytes = wire_of(c);
  if (bytes.empty()) return {};
  std::optional<std::vector<uint8_t>> out;
  switch (c.source) {
    case CommandSource::Supervisor:
      out = numbered<mm::SupervisorRequest_PubSubType>(bytes, [&](auto& m) {
        m.client_id(ids.client(m.client_id()));
        number_commands_sent(m, ids);
      });
      break;
    case CommandSource::Simulation:
      out = numbered<mm::SimulationRequest_PubSubType>(bytes, [&](auto& m) {
        m.client_id(ids.client(m.client_id()));
        number_commands_sent(m, ids);
      });
      break;
    case CommandSource::Pictures:
      out = numbered<mm::PictureRequest_PubSubType>(
          bytes, [&](auto& m) { m.client_id(ids.client(m.client_id())); });
      break;
    default:
      break;
  }
  return out ? *out : bytes;
}

std::vector<uint8_t> numbered_request(const RecordedRequest& r, Identities& ids) {
  std::optional<std::vector<uint8_t>> out;
  if (r.kind == RecordedRequest::Kind::Taken) {
    out = numbered<mm::SimulationRequest_PubSubType>(r.bytes, [&](auto& m) {
      m.client_id(ids.client(m.client_id()));
      number_commands_sent(m, ids);
    });
  } else {
    out = numbered<mm::SimulationReply_PubSubType>(
        r.bytes, [&](auto& m) { m.client_id(ids.client(m.client_id())); });
  }
  return out ? *out : r.bytes;
}

/// A command as a session line says it (its message's bytes compared apart).
std::string command_said(const Command& c) {
  std::string text = std::string(to_string(c.source)) + " " + std::string(operation_name(c));
  if (!c.target.empty()) text += " " + c.target;
  for (double v : c.robot ? c.robot->values() : std::vector<double>{})
    text += fmt::format(" {}", v);
  return text;
}

/// One record of a run, as compared: when it happened, what it is, and its content.
struct Record {
  uint64_t step = 0;
  std::string said;              // for the report
  std::vector<uint8_t> content;  // compared (with `said`)
};

std::string header_said(const SessionHeader& h) {
  return fmt::format(
      "header: seed {}, hash every {} steps, overlaps {}, {}, limits {} {} {}, snapshots {} {}, "
      "{}",
      h.seed, h.hash_every, h.overlaps_parted ? "parted" : "kept",
      h.strict ? "strict" : "not strict", h.limits.max_import_depth, h.limits.max_imported_files,
      h.limits.max_objects, h.snapshot_limits.max_count, h.snapshot_limits.max_bytes,
      h.self_contained ? "files embedded" : "files not embedded");
}

/// The run's records by kind, in the order each kind was written, identities numbered in the
/// order of the commands and requests (each kind's order is the run's).
struct Records {
  std::vector<Record> commands, requests, hashes, files;
};

Records records_of(const Session& s) {
  Records out;
  Identities ids;
  // Numbered in the order they ran: commands and requests interleaved by step, commands first
  // where a request was recorded after them.
  std::size_t c = 0, r = 0;
  while (c < s.commands.size() || r < s.requests.size()) {
    const bool command_next =
        r == s.requests.size() || (c < s.commands.size() && c < s.requests[r].commands_before);
    if (command_next) {
      const RecordedCommand& rc = s.commands[c++];
      Record rec;
      rec.step = rc.step;
      rec.said =
          fmt::format("command {} at step {}: {}{}", c, rc.step, command_said(rc.command),
                      rc.last_step > rc.step ? fmt::format(", held to step {}", rc.last_step) : "");
      rec.content = numbered_command(rc.command, ids);
      out.commands.push_back(std::move(rec));
    } else {
      const RecordedRequest& rr = s.requests[r++];
      Record rec;
      rec.step = rr.step;
      rec.said =
          fmt::format("request record {} after step {}: {} {}", r, rr.step,
                      rr.kind == RecordedRequest::Kind::Taken ? "taken" : "answered", rr.service);
      rec.content = numbered_request(rr, ids);
      out.requests.push_back(std::move(rec));
    }
  }
  for (std::size_t k = 0; k < s.hashes.size(); ++k) {
    const auto& h = s.hashes[k];
    out.hashes.push_back(
        {h.step, fmt::format("state hash after step {}: {:016x}", h.step, h.hash), {}});
  }
  for (std::size_t k = 0; k < s.files.size(); ++k) {
    const auto& f = s.files[k];
    // The world file's path as recorded aside: a file is its bytes, read after so many commands.
    Record rec;
    rec.step = f.commands_before < s.commands.size() ? s.commands[f.commands_before].step : s.steps;
    rec.said = fmt::format("file {} read after {} commands ({} bytes)", k + 1, f.commands_before,
                           f.bytes.size());
    rec.content.assign(f.bytes.begin(), f.bytes.end());
    out.files.push_back(std::move(rec));
  }
  return out;
}

bool same(const Record& a, const Record& b) { return a.said == b.said && a.content == b.content; }

}  // namespace

std::optional<std::string> first_difference(const Session& a, const Session& b) {
  if (header_said(a.header) != header_said(b.header))
    return "the headers: A " + header_said(a.header) + "; B " + header_said(b.header);
  const Records ra = records_of(a), rb = records_of(b);
  // Of each kind the first record that differs (or that one run has and the other not); of
  // those, the earliest.
  std::optional<std::string> first;
  uint64_t first_step = std::numeric_limits<uint64_t>::max();
  const auto look = [&](const std::vector<Record>& x, const std::vector<Record>& y) {
    const std::size_t n = std::max(x.size(), y.size());
    for (std::size_t k = 0; k < n; ++k) {
      if (k < x.size() && k < y.size() && same(x[k], y[k])) continue;
      const uint64_t step =
          std::min(k < x.size() ? x[k].step : y[k].step, k < y.size() ? y[k].step : x[k].step);
      if (step < first_step) {
        first_step = step;
        const auto side = [&](const std::vector<Record>& z) {
          if (k >= z.size()) return std::string("none (it ends before)");
          return z[k].said + (k < x.size() && k < y.size() && x[k].said == y[k].said
                                  ? " (its bytes differ)"
                                  : "");
        };
        first = "A " + side(x) + "; B " + side(y);
      }
      return;
    }
  };
  look(ra.commands, rb.commands);
  look(ra.requests, rb.requests);
  look(ra.hashes, rb.hashes);
  look(ra.files, rb.files);
  if (first) return first;
  if (a.steps != b.steps) return fmt::format("the end: A ran {} steps, B {}", a.steps, b.steps);
  return std::nullopt;
}

}  // namespace macsim
