#include "macsim/sim_core/session.h"

#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cinttypes>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <utility>

#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/runner.h"

namespace macsim {

// The format, one record a line, fields separated by one space:
//   macsim-session <version>
//   world <file>                         the world the session starts with
//   seed <N>                             its layout's seed, or -1: as written
//   hash-every <N>
//   overlaps parted|kept                 objects started inside each other: moved apart on load
//                                        or kept (version 2; a version 1 file reads as kept)
//   strict 0|1                           a world loaded later with objects inside each other is
//                                        refused (version 4, as the next two)
//   limits <import depth> <imported files> <objects>   what one world may hold
//   snapshots <count> <bytes>            named snapshots kept at most
//   wire-types <digest>                  the wire types the bytes below were written with, as
//                                        the recorder named them; "-": not named (version 6)
//   f <path> <checksum> <bytes>          a file the run read (the path as asked), embedded when
//                                        it was read: the bytes in hex, the checksum their XXH3
//                                        in 16 hex digits (version 4)
//   c <step> <source> <operation> <target> <values> <message> [<sender>]   a command, before
//                                        step+1; a robot command's sender, if known, as its
//                                        writer's id in 32 hex digits, ':' and the sample's
//                                        sequence number (version 6): a resumed simulator knows
//                                        which commands the killed one had
//   k <first> <last> [<robots>]          keep_robot_commands before each step first+1..last+1:
//                                        what a step request holding the robots' commands runs
//                                        once a step, as one record (version 3); the robots
//                                        held, comma-separated, when not all (version 4)
//   r <step> taken|answered <service> <bytes>   a request of a request/reply service taken
//                                        (a step request that began stepping: the request) or
//                                        answered (the reply) after `step` steps, in hex
//                                        (version 5): what a resume must not run twice
//   h <step> <hash>                      the state hash after `step` steps (16 hex digits)
//   end <steps> <commands> <hashes>      the closing line: counts of what came before
// Text fields are percent-encoded; an empty one is "-". Values are %.17g numbers joined by ",";
// a message is its bytes in hex.

namespace {

constexpr const char* kMagic = "macsim-session";

bool plain(unsigned char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
         std::strchr("._/:+-", c) != nullptr;
}

std::string encode(const std::string& text) {
  if (text.empty()) return "-";
  std::string out;
  for (unsigned char c : text) {
    if (plain(c) && !(c == '-' && text.size() == 1)) {
      out += static_cast<char>(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::optional<std::string> decode(const std::string& field) {
  if (field == "-") return std::string();
  std::string out;
  for (std::size_t i = 0; i < field.size(); ++i) {
    if (field[i] != '%') {
      if (!plain(static_cast<unsigned char>(field[i]))) return std::nullopt;
      out += field[i];
      continue;
    }
    if (i + 2 >= field.size()) return std::nullopt;
    const int hi = hex_digit(field[i + 1]), lo = hex_digit(field[i + 2]);
    if (hi < 0 || lo < 0) return std::nullopt;
    out += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  return out;
}

std::string values_text(const std::vector<double>& values) {
  if (values.empty()) return "-";
  std::string out;
  for (double v : values) {
    char number[40];
    std::snprintf(number, sizeof number, "%.17g", v);
    if (!out.empty()) out += ',';
    out += number;
  }
  return out;
}

std::string bytes_text(std::string_view bytes) {
  if (bytes.empty()) return "-";
  static const char* digits = "0123456789abcdef";
  std::string out;
  out.reserve(bytes.size() * 2);
  for (unsigned char b : bytes) {
    out += digits[b >> 4];
    out += digits[b & 15];
  }
  return out;
}

std::string bytes_text(const std::vector<uint8_t>& bytes) {
  return bytes_text(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

/// A robot command's sender: its writer's id (32 hex digits), ':', the sample's sequence number.
std::string sender_text(const Sender& s) {
  return bytes_text(std::string_view(reinterpret_cast<const char*>(s.id.data()), s.id.size())) +
         ":" + std::to_string(s.sequence);
}

std::string command_line(uint64_t step, const Command& c) {
  return "c " + std::to_string(step) + " " + std::string(to_string(c.source)) + " " +
         encode(std::string(operation_name(c))) + " " + encode(c.target) + " " +
         values_text(c.robot ? c.robot->values() : std::vector<double>{}) + " " +
         bytes_text(wire_of(c)) + (c.robot && c.sent_by ? " " + sender_text(*c.sent_by) : "") +
         "\n";
}

std::string hex16(uint64_t v) {
  char text[20];
  std::snprintf(text, sizeof text, "%016" PRIx64, v);
  return text;
}

std::string hash_line(uint64_t step, uint64_t hash) {
  return "h " + std::to_string(step) + " " + hex16(hash) + "\n";
}

std::string request_line(uint64_t step, const RecordedRequest& r) {
  return "r " + std::to_string(step) + " " +
         (r.kind == RecordedRequest::Kind::Taken ? "taken " : "answered ") + encode(r.service) +
         " " + bytes_text(r.bytes) + "\n";
}

std::string file_line(const std::string& path, const std::string& bytes) {
  return "f " + encode(path) + " " + hex16(file_checksum(bytes)) + " " +
         bytes_text(std::string_view(bytes)) + "\n";
}

}  // namespace

namespace detail {
/// A step request that holds the robots' commands runs keep_robot_commands once a step; a run
/// of them at consecutive steps is written as one record (k), so that a file grows with what
/// happened, not with the steps taken.
struct KeepRun {
  bool open = false;
  uint64_t first = 0, last = 0;
  std::string robots;  // held, comma-separated; empty: every robot

  static bool is_keep(const Command& c) {
    return c.source == CommandSource::Simulation && c.request_as<KeepRobotCommands>() != nullptr;
  }
  /// The run's record, if one is open; closes it.
  std::string close() {
    if (!open) return {};
    open = false;
    return "k " + std::to_string(first) + " " + std::to_string(last) +
           (robots.empty() ? "" : " " + encode(robots)) + "\n";
  }
  /// The text a command adds to the file: nothing while it extends the run.
  std::string add(uint64_t step, const Command& c) {
    if (!is_keep(c)) return close() + command_line(step, c);
    if (open && step == last + 1 && c.target == robots) {
      last = step;
      return {};
    }
    std::string before = close();
    *this = {true, step, step, c.target};
    return before;
  }
};
}  // namespace detail

namespace {
using detail::KeepRun;

/// The most steps one k record may name (a read expands it into one command a step).
constexpr uint64_t kMaxRunSteps = 10'000'000;

/// Reads one file's lines, each error naming file and line.
struct LineReader {
  std::string path;
  int line = 0;

  [[noreturn]] void fail(const std::string& what) const {
    throw SessionFileError(path + ":" + std::to_string(line) + ": " + what);
  }

  uint64_t number(const std::string& field, const char* what) const {
    if (field.empty() || field.find_first_not_of("0123456789") != std::string::npos)
      fail(std::string(what) + " must be a whole number; got '" + field + "'");
    errno = 0;
    const unsigned long long n = std::strtoull(field.c_str(), nullptr, 10);
    if (errno == ERANGE) fail(std::string(what) + " is too large: " + field);
    return n;
  }

  std::vector<double> values(const std::string& field) const {
    std::vector<double> out;
    if (field == "-") return out;
    std::stringstream parts(field);
    std::string part;
    while (std::getline(parts, part, ',')) {
      double v = 0;
      const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), v);
      if (part.empty() || error != std::errc() || end != part.data() + part.size() ||
          !std::isfinite(v)) {
        fail("a command's values must be finite numbers; got '" + part + "'");
      }
      out.push_back(v);
    }
    if (field.empty() || field.back() == ',') fail("a command's values are empty or end with ','");
    return out;
  }

  std::vector<uint8_t> bytes(const std::string& field, const char* what) const {
    std::vector<uint8_t> out;
    if (field == "-") return out;
    if (field.size() % 2 != 0) fail(std::string(what) + " must be pairs of hex digits");
    for (std::size_t i = 0; i < field.size(); i += 2) {
      const int hi = hex_digit(field[i]), lo = hex_digit(field[i + 1]);
      if (hi < 0 || lo < 0)
        fail(std::string(what) + " must be hex digits; got '" + field.substr(i, 2) + "'");
      out.push_back(static_cast<uint8_t>(hi * 16 + lo));
    }
    return out;
  }

  Sender sender(const std::string& field) const {
    const std::size_t colon = field.find(':');
    if (colon != 32)
      fail("a command's sender must be its writer's id in 32 hex digits, ':' and a number; got '" +
           field.substr(0, 60) + "'");
    const auto id = bytes(field.substr(0, 32), "a sender's id");
    Sender s;
    std::copy(id.begin(), id.end(), s.id.begin());
    s.sequence = number(field.substr(33), "a sender's sequence number");
    return s;
  }

  std::string text(const std::string& field, const char* what) const {
    auto decoded = decode(field);
    if (!decoded) fail(std::string(what) + " is not a percent-encoded text: '" + field + "'");
    return *decoded;
  }
};

std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t space = line.find(' ', start);
    fields.push_back(line.substr(start, space - start));
    if (space == std::string::npos) return fields;
    start = space + 1;
  }
}

void write_all(std::FILE* file, const std::string& path, const std::string& text) {
  if (std::fwrite(text.data(), 1, text.size(), file) != text.size())
    throw SessionFileError(path + ": cannot write: " + std::strerror(errno));
}

std::string header_text(const SessionHeader& header) {
  const auto& l = header.limits;
  return std::string(kMagic) + " " + std::to_string(kSessionFormatVersion) + "\nworld " +
         encode(header.world_file) + "\nseed " + std::to_string(header.seed) + "\nhash-every " +
         std::to_string(header.hash_every) + "\noverlaps " +
         (header.overlaps_parted ? "parted" : "kept") + "\nstrict " + (header.strict ? "1" : "0") +
         "\nlimits " + std::to_string(l.max_import_depth) + " " +
         std::to_string(l.max_imported_files) + " " + std::to_string(l.max_objects) +
         "\nsnapshots " + std::to_string(header.snapshot_limits.max_count) + " " +
         std::to_string(header.snapshot_limits.max_bytes) + "\nwire-types " +
         encode(header.wire_types) + "\n";
}

}  // namespace

SessionWriter::SessionWriter(const std::string& path, const SessionHeader& header)
    : path_(path), hash_every_(header.hash_every), keep_run_(std::make_unique<KeepRun>()) {
  if (hash_every_ == 0)
    throw SessionFileError(path + ": the hash interval must be 1 or more steps");
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw SessionFileError(path + ": cannot write: " + std::strerror(errno));
  write_all(file_, path_, header_text(header));
}

SessionWriter::SessionWriter(const std::string& path, const Session& read)
    : path_(path), hash_every_(read.header.hash_every), keep_run_(std::make_unique<KeepRun>()) {
  if (hash_every_ == 0)
    throw SessionFileError(path + ": the hash interval must be 1 or more steps");
  for (const auto& c : read.commands) commands_ += c.count();
  hashes_ = read.hashes.size();
  for (const auto& f : read.files) embedded_[f.path] = file_checksum(f.bytes);
  // What follows the last whole record (a line cut by the kill, the closing line) goes.
  if (::truncate(path.c_str(), static_cast<off_t>(read.whole_bytes)) != 0)
    throw SessionFileError(path + ": cannot write: " + std::strerror(errno));
  file_ = std::fopen(path.c_str(), "a");
  if (!file_) throw SessionFileError(path + ": cannot write: " + std::strerror(errno));
}

SessionWriter::~SessionWriter() {
  if (file_) std::fclose(file_);  // no closing line: the file reads as cut short
}

void SessionWriter::put(const std::string& text) {
  if (!file_) return;
  if (std::fwrite(text.data(), 1, text.size(), file_) == text.size()) return;
  log_message(LogLevel::Error, "macsim: cannot write the session " + path_ + " (" +
                                   std::strerror(errno) + "): recording stopped");
  std::fclose(file_);
  file_ = nullptr;
}

void SessionWriter::command(uint64_t step, const Command& command) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string text = keep_run_->add(step, command);
  put(text);
  ++commands_;
  // In the kernel's hands before the command acts: a process killed now keeps it.
  if (file_ && !text.empty()) std::fflush(file_);
}

void SessionWriter::request(uint64_t step, const RecordedRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  put(keep_run_->close() + request_line(step, request));
  if (file_) std::fflush(file_);
}

void SessionWriter::file(const std::string& path, const std::string& bytes) {
  const uint64_t checksum = file_checksum(bytes);
  std::lock_guard<std::mutex> lock(mutex_);
  auto [embedded, added] = embedded_.emplace(path, checksum);
  if (!added && embedded->second == checksum) return;  // the same bytes: embedded already
  embedded->second = checksum;
  // A run of held steps ends before the file: it was read after them.
  put(keep_run_->close() + file_line(path, bytes));
  if (file_) std::fflush(file_);
}

void SessionWriter::hash(uint64_t step, uint64_t hash) {
  std::lock_guard<std::mutex> lock(mutex_);
  put(keep_run_->close() + hash_line(step, hash));
  ++hashes_;
  if (file_) std::fflush(file_);
}

void SessionWriter::finish(uint64_t steps) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!file_) return;
  put(keep_run_->close() + "end " + std::to_string(steps) + " " + std::to_string(commands_) + " " +
      std::to_string(hashes_) + "\n");
  if (!file_) return;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  finished_ = closed;
  if (!closed) {
    log_message(LogLevel::Error,
                "macsim: cannot write the session " + path_ + " (" + std::strerror(errno) + ")");
  }
}

Session read_session(const std::string& path, SessionRead read) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw SessionFileError(path + ": cannot read: " + std::strerror(errno));
  std::stringstream text;
  text << file.rdbuf();
  return parse_session(text.str(), path, read);
}

namespace {

/// Reads a session's lines one by one into `session`: the first line (format version), the
/// header, then the records (files, commands, runs, requests, hashes) and the closing line.
struct SessionParser {
  explicit SessionParser(const std::string& path) : r{path} {}

  /// The first line: "macsim-session <version>", and what that version's header must hold.
  void first_line(const std::vector<std::string>& f) {
    if (f.size() != 2 || f[0] != kMagic)
      r.fail("not a macsim session file (its first line must be 'macsim-session <version>')");
    for (int v = 1; v <= kSessionFormatVersion; ++v) {
      if (f[1] == std::to_string(v)) version = v;
    }
    if (version == 0) {
      r.fail("session format version " + f[1] + "; this macsim reads versions 1 to " +
             std::to_string(kSessionFormatVersion));
    }
    session.version = version;
    if (version == 1) {
      session.header.overlaps_parted = false;  // recorded before macsim parted them
    } else {
      has_overlaps = false;
    }
    session.header.self_contained = version >= 4;
    if (version >= 4) has_settings = false;
    if (version >= 6) has_wire_types = false;
  }

  /// Fails naming the header lines this version needs when a record comes before them.
  void check_header_before(const std::vector<std::string>& f) {
    const bool header_line =
        f[0] == "world" || f[0] == "seed" || f[0] == "hash-every" || f[0] == "overlaps" ||
        (version >= 4 && (f[0] == "strict" || f[0] == "limits" || f[0] == "snapshots")) ||
        (version >= 6 && f[0] == "wire-types");
    if (version >= 4) has_settings = has_strict && has_limits && has_snapshots;
    if (header_line ||
        (has_world && has_seed && has_every && has_overlaps && has_settings && has_wire_types))
      return;
    std::string missing;  // the lines this version's header lacks, by name
    for (const auto& [name, has] :
         {std::pair{"world", has_world}, std::pair{"seed", has_seed},
          std::pair{"hash-every", has_every}, std::pair{"overlaps", has_overlaps},
          std::pair{"strict", has_strict || version < 4},
          std::pair{"limits", has_limits || version < 4},
          std::pair{"snapshots", has_snapshots || version < 4},
          std::pair{"wire-types", has_wire_types}}) {
      if (!has) missing += std::string(missing.empty() ? "" : ", ") + "'" + name + "'";
    }
    r.fail("the header needs its " + missing + " line(s) before any record");
  }

  /// A header line (each once); false when the line is none.
  bool header_line(const std::vector<std::string>& f) {
    SessionHeader& h = session.header;
    if (f[0] == "world" && f.size() == 2 && !has_world) {
      h.world_file = r.text(f[1], "the world file");
      has_world = true;
    } else if (f[0] == "seed" && f.size() == 2 && !has_seed) {
      h.seed = f[1] == "-1" ? -1 : static_cast<int64_t>(r.number(f[1], "the seed"));
      if (h.seed > INT32_MAX) r.fail("the seed must be -1 or 0 to 2147483647");
      has_seed = true;
    } else if (f[0] == "hash-every" && f.size() == 2 && !has_every) {
      h.hash_every = r.number(f[1], "hash-every");
      if (h.hash_every == 0) r.fail("hash-every must be 1 or more");
      has_every = true;
    } else if (f[0] == "overlaps" && f.size() == 2 && !has_overlaps) {
      if (f[1] != "parted" && f[1] != "kept")
        r.fail("overlaps must be 'parted' or 'kept'; got '" + f[1].substr(0, 20) + "'");
      h.overlaps_parted = f[1] == "parted";
      has_overlaps = true;
    } else if (f[0] == "strict" && f.size() == 2 && version >= 4 && !has_strict) {
      if (f[1] != "0" && f[1] != "1")
        r.fail("strict must be 0 or 1; got '" + f[1].substr(0, 20) + "'");
      h.strict = f[1] == "1";
      has_strict = true;
    } else if (f[0] == "limits" && f.size() == 4 && version >= 4 && !has_limits) {
      auto& l = h.limits;
      l.max_import_depth = r.number(f[1], "the import depth");
      l.max_imported_files = r.number(f[2], "the imported files");
      l.max_objects = r.number(f[3], "the objects");
      if (l.max_import_depth == 0 || l.max_imported_files == 0 || l.max_objects == 0)
        r.fail("each limit must be 1 or more");
      has_limits = true;
    } else if (f[0] == "snapshots" && f.size() == 3 && version >= 4 && !has_snapshots) {
      auto& l = h.snapshot_limits;
      l.max_count = r.number(f[1], "the snapshot count");
      l.max_bytes = r.number(f[2], "the snapshot bytes");
      if (l.max_count == 0) r.fail("the snapshot count must be 1 or more");
      has_snapshots = true;
    } else if (f[0] == "wire-types" && f.size() == 2 && version >= 6 && !has_wire_types) {
      h.wire_types = r.text(f[1], "the wire types");
      has_wire_types = true;
    } else {
      return false;
    }
    return true;
  }

  /// "f PATH CHECKSUM BYTES": a file the run read, embedded.
  void file_record(const std::vector<std::string>& f) {
    EmbeddedFile file;
    file.path = r.text(f[1], "the file's path");
    if (file.path.empty()) r.fail("an embedded file must name its path");
    if (f[2].size() != 16 || f[2].find_first_not_of("0123456789abcdef") != std::string::npos)
      r.fail("a file's checksum must be 16 hex digits; got '" + f[2].substr(0, 20) + "'");
    const auto bytes = r.bytes(f[3], "an embedded file's bytes");
    file.bytes.assign(bytes.begin(), bytes.end());
    if (hex16(file_checksum(file.bytes)) != f[2]) {
      r.fail("the embedded file '" + file.path +
             "' does not match its checksum: it was altered after it was recorded");
    }
    file.commands_before = session.commands.size();
    session.files.push_back(std::move(file));
  }

  /// A recorded request: the runner's own as their types (a world load, the robots' commands
  /// kept), a server's as its name and bytes (replay_session() has them read as typed).
  static std::shared_ptr<const Request> request_of(CommandSource source, const std::string& name,
                                                   std::vector<uint8_t> bytes) {
    if (source == CommandSource::Simulation) {
      const std::string text(bytes.begin(), bytes.end());
      if (name == "load_world" || name == "load_world_xml") {
        auto load = std::make_shared<LoadWorldRequest>();
        (name == "load_world" ? load->file : load->xml) = text;
        return load;
      }
      if (name == "keep_robot_commands" && bytes.empty())
        return std::make_shared<KeepRobotCommands>();
    }
    auto wire = std::make_shared<WireRequest>();
    wire->operation = name;
    wire->bytes = std::move(bytes);
    return wire;
  }

  /// "c STEP SOURCE OPERATION TARGET VALUES MESSAGE [SENDER]": a command at its step.
  void command_record(const std::vector<std::string>& f) {
    RecordedCommand rc;
    rc.step = r.number(f[1], "a command's step");
    const auto source = command_source(f[2]);
    if (!source || *source == CommandSource::Local) r.fail("unknown command source '" + f[2] + "'");
    rc.command.source = *source;
    const std::string operation = r.text(f[3], "the operation");
    rc.command.target = r.text(f[4], "the target");
    const auto values = r.values(f[5]);
    std::vector<uint8_t> message = r.bytes(f[6], "a command's message");
    if (operation.empty()) r.fail("a command must name its operation");
    if (rc.command.source == CommandSource::Robot) {
      std::string why;
      rc.command.robot = robot::decode_command(operation, values, &why);
      if (!rc.command.robot) r.fail(why);
    } else if (!values.empty()) {
      r.fail("only a robot command carries numbers");
    } else {
      rc.command.request = request_of(rc.command.source, operation, std::move(message));
    }
    if (f.size() == 8) {
      if (rc.command.source != CommandSource::Robot) r.fail("only a robot command has a sender");
      rc.command.sent_by = r.sender(f[7]);
    }
    advance_to(rc.step);
    rc.last_step = rc.step;
    ++commands;
    session.commands.push_back(std::move(rc));
  }

  /// "k FIRST LAST [ROBOTS]": the robots' commands kept in force over a run of steps.
  void run_record(const std::vector<std::string>& f) {
    const uint64_t first = r.number(f[1], "a run's first step");
    const uint64_t last = r.number(f[2], "a run's last step");
    if (last < first) r.fail("a run ends before it starts");
    if (first < last_step) r.fail("steps must not go back");
    if (last - first >= kMaxRunSteps)
      r.fail("a run of more than " + std::to_string(kMaxRunSteps) + " steps");
    RecordedCommand keep;  // one record however many steps it holds
    keep.command = request_command<KeepRobotCommands>(CommandSource::Simulation);
    if (f.size() == 4) {
      keep.command.target = r.text(f[3], "the robots held");
      if (keep.command.target.empty()) r.fail("a run names no robot to hold");
    }
    keep.step = first;
    keep.last_step = last;
    commands += keep.count();
    session.commands.push_back(std::move(keep));
    last_step = last;
  }

  /// "r STEP taken|answered SERVICE BYTES": a request taken or answered at its step.
  void request_record(const std::vector<std::string>& f) {
    RecordedRequest request;
    request.step = r.number(f[1], "a request's step");
    if (f[2] != "taken" && f[2] != "answered")
      r.fail("a request is 'taken' or 'answered'; got '" + f[2].substr(0, 20) + "'");
    request.kind = f[2] == "taken" ? RecordedRequest::Kind::Taken : RecordedRequest::Kind::Answered;
    request.service = r.text(f[3], "the service");
    if (request.service.empty()) r.fail("a request must name its service");
    request.bytes = r.bytes(f[4], "a request's bytes");
    if (request.bytes.empty()) r.fail("a request's bytes are empty");
    advance_to(request.step);
    request.commands_before = session.commands.size();
    session.requests.push_back(std::move(request));
  }

  /// "h STEP HASH": the state hash at a step.
  void hash_record(const std::vector<std::string>& f) {
    RecordedHash h;
    h.step = r.number(f[1], "a hash's step");
    if (f[2].size() != 16 || f[2].find_first_not_of("0123456789abcdef") != std::string::npos)
      r.fail("a hash must be 16 hex digits; got '" + f[2] + "'");
    h.hash = std::strtoull(f[2].c_str(), nullptr, 16);
    advance_to(h.step);
    session.hashes.push_back(h);
  }

  /// "end STEPS COMMANDS HASHES": the closing line, its counts those of the records before it.
  void end_record(const std::vector<std::string>& f) {
    session.steps = r.number(f[1], "the steps");
    if (session.steps < last_step) r.fail("the session ends before its last record");
    if (r.number(f[2], "the command count") != commands ||
        r.number(f[3], "the hash count") != session.hashes.size()) {
      r.fail("the closing line's counts do not match the records before it (" +
             std::to_string(commands) + " commands, " + std::to_string(session.hashes.size()) +
             " hashes): lines are missing");
    }
    ended = true;
  }

  /// One line after the first: a header line or a record, else a failure naming the line.
  void line(const std::string& text) {
    if (ended) r.fail("nothing may follow the closing 'end' line");
    const auto f = fields_of(text);
    if (r.line == 1) return first_line(f);
    check_header_before(f);
    if (header_line(f)) return;
    if (f[0] == "f" && f.size() == 4 && version >= 4) return file_record(f);
    if (f[0] == "c" && (f.size() == 7 || (f.size() == 8 && version >= 6))) return command_record(f);
    if (f[0] == "k" && (f.size() == 3 || (f.size() == 4 && version >= 4)) && version >= 3)
      return run_record(f);
    if (f[0] == "r" && f.size() == 5 && version >= 5) return request_record(f);
    if (f[0] == "h" && f.size() == 3) return hash_record(f);
    if (f[0] == "end" && f.size() == 4) return end_record(f);
    r.fail("not a session record: '" + text.substr(0, 60) + "'");
  }

  /// A record's step: never before the one before it.
  void advance_to(uint64_t step) {
    if (step < last_step) r.fail("steps must not go back");
    last_step = step;
  }

  LineReader r;
  Session session;
  bool ended = false, has_world = false, has_every = false, has_seed = false;
  bool has_overlaps = true;  // a version 2 file must say (first_line); version 1 had no parting
  bool has_settings = true;  // strict, limits and snapshots: a version 4 file must say
  bool has_strict = false, has_limits = false, has_snapshots = false;
  bool has_wire_types = true;  // a version 6 file must say
  uint64_t last_step = 0;
  uint64_t commands = 0;  // as many as ran: a run of held steps counts each step
  int version = 0;
};

}  // namespace

Session parse_session(const std::string& text, const std::string& path, SessionRead read) {
  const bool resuming = read == SessionRead::UpToLastWholeRecord;
  // A resume reads up to the last whole line: a kill may have cut the one after it.
  const std::string whole = resuming && !text.empty() && text.back() != '\n'
                                ? text.substr(0, text.rfind('\n') + 1)
                                : text;
  std::istringstream in(whole);
  if (!whole.empty() && whole.back() != '\n') {
    throw SessionFileError(path + ":" +
                           std::to_string(std::count(whole.begin(), whole.end(), '\n') + 1) +
                           ": the file is cut short (its last line is incomplete)");
  }
  std::size_t offset = 0;  // bytes read before this line
  SessionParser parser(path);
  Session& session = parser.session;
  std::string line;
  while (std::getline(in, line)) {
    ++parser.r.line;
    offset += line.size() + 1;
    parser.line(line);
    // The whole records' bytes, from the header on: the closing line is none.
    if (parser.r.line > 1) session.whole_bytes = parser.ended ? offset - line.size() - 1 : offset;
  }
  if (parser.r.line == 0) throw SessionFileError(path + ": empty, not a session file");
  if (resuming && !parser.ended) {
    if (session.commands.empty() && session.hashes.empty() && session.requests.empty())
      throw SessionFileError(path + ":" + std::to_string(parser.r.line) +
                             ": the session holds no record to resume from");
    session.cut_short = true;
    session.steps = parser.last_step;
    return std::move(session);
  }
  if (!parser.ended) {
    throw SessionFileError(path + ":" + std::to_string(parser.r.line) +
                           ": the file is cut short (no closing 'end' line): the simulator did "
                           "not stop cleanly, or the file was truncated");
  }
  return std::move(session);
}

void write_session(const std::string& path, const Session& session) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw SessionFileError(path + ": cannot write: " + std::strerror(errno));
  std::string text = header_text(session.header);
  // Commands before a hash of the same step ran before it: they come first. A file or a
  // request comes before the first command recorded after it, a request after the hashes of
  // its step.
  std::size_t h = 0, f = 0, q = 0;
  KeepRun run;
  const auto files_until = [&](std::size_t commands) {
    for (; f < session.files.size() && session.files[f].commands_before <= commands; ++f)
      text += run.close() + file_line(session.files[f].path, session.files[f].bytes);
  };
  const auto requests_until = [&](std::size_t commands, uint64_t before_step) {
    for (; q < session.requests.size() && session.requests[q].commands_before <= commands &&
           session.requests[q].step < before_step;
         ++q)
      text += run.close() + request_line(session.requests[q].step, session.requests[q]);
  };
  const auto hashes_until = [&](std::size_t commands, uint64_t through_step) {
    for (; h < session.hashes.size() && session.hashes[h].step <= through_step; ++h) {
      requests_until(commands, session.hashes[h].step);
      text += run.close() + hash_line(session.hashes[h].step, session.hashes[h].hash);
    }
  };
  files_until(0);  // what the first world was read from, before its first hash
  uint64_t commands = 0;
  for (std::size_t i = 0; i < session.commands.size(); ++i) {
    const auto& c = session.commands[i];
    hashes_until(i, c.step);
    requests_until(i, UINT64_MAX);
    files_until(i);
    if (c.count() == 1) {
      text += run.add(c.step, c.command);
    } else {  // a run read back: its record again (a hash within it would have split it)
      text += run.close() + "k " + std::to_string(c.step) + " " + std::to_string(c.last_step) +
              (c.command.target.empty() ? "" : " " + encode(c.command.target)) + "\n";
    }
    commands += c.count();
  }
  text += run.close();
  files_until(session.commands.size());
  hashes_until(session.commands.size(), UINT64_MAX);
  requests_until(session.commands.size(), UINT64_MAX);
  text += "end " + std::to_string(session.steps) + " " + std::to_string(commands) + " " +
          std::to_string(session.hashes.size()) + "\n";
  const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
  if (std::fclose(file) != 0 || !written)
    throw SessionFileError(path + ": cannot write: " + std::strerror(errno));
}

uint64_t file_checksum(const std::string& bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

void embed_first_files(const Session& session, MemoryFiles& files) {
  for (const auto& f : session.files) {
    if (f.commands_before > 0) break;
    files.add(f.path, f.bytes);
  }
}

ReplayOutcome replay_session(const Session& session, Runner& runner, const SessionWorldLoader& load,
                             MemoryFiles* files, const std::function<void()>& after_step,
                             const RequestReader& read) {
  ReplayOutcome out;
  std::size_t c = 0, h = 0, f = 0;
  const auto hex = hex16;
  for (uint64_t step = 0;; ++step) {
    // The hash after `step` steps was taken before the commands that ran at that step.
    for (; h < session.hashes.size() && session.hashes[h].step == step; ++h) {
      const uint64_t now = runner.world().state_hash();
      ++out.hashes_checked;
      if (now != session.hashes[h].hash) {
        out.equal = false;
        out.first_difference = step;
        out.recorded_hash = session.hashes[h].hash;
        out.replayed_hash = now;
        out.steps = step;
        out.message = "the replay differs at step " + std::to_string(step) +
                      " (t = " + std::to_string(runner.world().time()) + " s): recorded hash " +
                      hex(out.recorded_hash) + ", replayed " + hex(now) +
                      "; the last equal hash was at step " + std::to_string(out.last_equal);
        return out;
      }
      out.last_equal = step;
    }
    // Each command recorded before this step; a run stays at hand until its last step.
    for (; c < session.commands.size() && session.commands[c].step <= step; ++c) {
      // What the recorded run had read before this command, as it read it.
      for (; files && f < session.files.size() && session.files[f].commands_before <= c; ++f)
        files->add(session.files[f].path, session.files[f].bytes);
      const RecordedCommand& recorded = session.commands[c];
      if (recorded.count() > 1) {
        runner.execute(recorded.command);
        ++out.commands_run;
        if (step < recorded.last_step) break;  // again before the next step
        continue;
      }
      Command command = recorded.command;
      if (read && command.request_as<WireRequest>()) {  // the server's typed request
        auto typed = read(command);
        if (!typed) {  // no server records such a request: the file was altered
          out.equal = false;
          out.steps = step;
          out.message = "the replay cannot read command " + std::to_string(c + 1) + " (step " +
                        std::to_string(recorded.step) + ", " + describe(command) +
                        "): its bytes are no request its server records";
          return out;
        }
        command.request = std::move(typed);
      }
      if (auto parse = load(command)) {
        std::optional<LoadOutcome> loaded;
        (void)runner.load(
            std::move(parse), [&loaded](const LoadOutcome& o) { loaded = o; }, command);
        while (!loaded) {
          runner.wait_for_commands(std::chrono::steady_clock::now() + std::chrono::seconds(1));
          runner.apply_commands();
        }
        if (!loaded->ok) {  // the live run loaded it: the replay cannot go on without it
          out.equal = false;
          out.steps = step;
          out.message = "the replay cannot load the world the session loaded at step " +
                        std::to_string(step) + ": " + loaded->error;
          return out;
        }
      } else {
        // What the recorded run had heard of its sender: a step request naming it waits no more
        // (a resumed simulator, whose clients name what the killed one took).
        if (command.sent_by) runner.note_arrival(*command.sent_by);
        runner.execute(command);
      }
      ++out.commands_run;
    }
    if (step >= session.steps) break;
    runner.step();
    if (after_step) after_step();
  }
  out.steps = session.steps;
  out.message = "replayed " + std::to_string(out.steps) + " steps and " +
                std::to_string(out.commands_run) + " commands: all " +
                std::to_string(out.hashes_checked) + " hashes equal";
  return out;
}

}  // namespace macsim
