// A session: every command that reached the world, with the step it ran at, the world's state
// hash every N steps, every file the run read (the world, its imports and textures, worlds
// loaded later) and every setting that changes results. Recorded by a running simulator,
// replayed from the file alone, in any folder, to the same hashes; a replay stops at the first
// step whose hash differs. A bug report is one file.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "macsim/sim_core/command.h"
#include "macsim/sim_core/snapshot_store.h"
#include "macsim/sim_core/world_loader.h"
#include "macsim/sim_core/world_spec.h"

namespace macsim {

class Runner;

/// The version of the session format this build writes and reads (its first line).
/// Version 2 added the header's `overlaps` line, version 3 the `k` record (a run of steps
/// that held the robots' commands), version 4 the files read (`f`) and the settings (`strict`,
/// `limits`, `snapshots`), version 5 the requests taken and answered (`r`), version 6 the wire
/// types its bytes were written with (`wire-types`) and each robot command's sender; versions 1
/// to 5 are still read (the files of versions 1 to 3 from the disk).
inline constexpr int kSessionFormatVersion = 6;

/// A session file that cannot be read: names the file and line.
class SessionFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a session starts from.
struct SessionHeader {
  std::string world_file;     ///< the world the session started with, as it was named
  int64_t seed = -1;          ///< the layout's seed (macsim --seed), or -1: as written
  uint64_t hash_every = 100;  ///< steps between two recorded state hashes
  /// Objects that started inside each other were moved apart on load (part_overlaps()); false
  /// when kept where the file put them (macsim --keep-overlaps or --strict, and version 1).
  bool overlaps_parted = true;
  /// A world loaded later whose objects start inside each other is refused (macsim --strict).
  bool strict = false;
  LoadLimits limits;               ///< what one world may hold (macsim --max-objects, ...)
  SnapshotLimits snapshot_limits;  ///< named snapshots kept at most (--max-snapshots, ...)
  /// The file holds the files the run read (version 4): a replay reads nothing else.
  bool self_contained = true;
  /// The digest of the wire types its requests' and messages' bytes were written with, as the
  /// recording program named them (version 6); empty: not named (version 5 and older).
  std::string wire_types;
};

/// A file the recorded run read, as it read it (the path as it was asked for).
struct EmbeddedFile {
  std::string path;
  std::string bytes;
  std::size_t commands_before = 0;  ///< commands recorded before it: it was read after them
};

/// A command and the runner's step count when it ran (before that step).
struct RecordedCommand {
  uint64_t step = 0;
  Command command;
  /// A run (a `k` record): the same command before every step from `step` to `last_step`;
  /// equal to `step` for one command.
  uint64_t last_step = 0;
  /// How many commands it stands for.
  uint64_t count() const { return last_step > step ? last_step - step + 1 : 1; }
};

/// A request of a request/reply service taken or answered after `step` steps (version 5): what
/// a resumed simulator must know not to run a request twice, and to finish one it had begun.
struct RecordedRequest {
  enum class Kind { Taken, Answered };
  uint64_t step = 0;
  Kind kind = Kind::Answered;
  std::string service;              ///< the service's name, e.g. "simulation"
  std::vector<uint8_t> bytes;       ///< taken: the request, answered: the reply, as on the wire
  std::size_t commands_before = 0;  ///< commands recorded before it
};

/// The world's state hash after `step` steps.
struct RecordedHash {
  uint64_t step = 0;
  uint64_t hash = 0;
};

/// A whole session file.
struct Session {
  int version = kSessionFormatVersion;  ///< the format version it was written in
  SessionHeader header;
  std::vector<RecordedCommand> commands;  ///< in the order they ran (a run of held steps is one)
  std::vector<RecordedHash> hashes;       ///< by step
  std::vector<EmbeddedFile> files;        ///< in the order they were read
  std::vector<RecordedRequest> requests;  ///< in the order they were taken or answered
  uint64_t steps = 0;                     ///< steps run when it ended (or at its last record)
  /// Read for resuming (SessionRead::UpToLastWholeRecord): the file had no closing line (its
  /// writer was killed), and the bytes of its last whole record end here.
  bool cut_short = false;
  std::size_t whole_bytes = 0;  ///< the file's bytes up to its last record (closing line not)
};

/// How much of a session file read_session() takes.
enum class SessionRead {
  Whole,                ///< the whole file with its closing line (a replay)
  UpToLastWholeRecord,  ///< up to its last whole record (a resume after a kill)
};

namespace detail {
struct KeepRun;  // session.cpp
}  // namespace detail

/// Writes a session as the simulation runs (on the simulation thread; file() on any thread).
/// Once a write fails (a full disk) it says so in the log (log_sink.h), once, and writes no
/// more: the file then reads as cut short.
class SessionWriter {
 public:
  /// Opens `path` for writing and writes the header; throws SessionFileError if it cannot.
  SessionWriter(const std::string& path, const SessionHeader& header);
  /// Goes on writing the session `read` from `path` (read for resuming): cuts the file after
  /// its last whole record and appends, counting on from what it holds.
  SessionWriter(const std::string& path, const Session& read);
  ~SessionWriter();
  SessionWriter(const SessionWriter&) = delete;
  SessionWriter& operator=(const SessionWriter&) = delete;

  /// Writes a command that ran before step `step` + 1; on disk before this returns (a write per
  /// command: a process killed after it keeps it; a machine crash may lose what the kernel had
  /// not written back), except a held step extending a run (`k`), written when the run ends.
  void command(uint64_t step, const Command& command);
  /// Writes a request taken or answered after `step` steps; on disk before this returns.
  void request(uint64_t step, const RecordedRequest& request);
  /// Embeds a file the run read (its path as asked), now, unless the same bytes were embedded
  /// under that path before; flushed at once.
  void file(const std::string& path, const std::string& bytes);
  /// Writes a hash line and flushes: a simulator killed keeps what came before it on disk.
  void hash(uint64_t step, uint64_t hash);
  /// Writes the closing line (a file without it is refused as cut short) and closes; later
  /// calls do nothing.
  void finish(uint64_t steps);
  /// False once a write failed.
  bool ok() const { return file_ != nullptr || finished_; }
  uint64_t hash_every() const { return hash_every_; }
  uint64_t commands() const { return commands_; }

 private:
  mutable std::mutex mutex_;                  // file() comes from a world's loader thread too
  std::map<std::string, uint64_t> embedded_;  // path -> checksum of the bytes embedded last
  std::FILE* file_ = nullptr;
  std::string path_;
  uint64_t hash_every_;
  uint64_t commands_ = 0, hashes_ = 0;
  bool finished_ = false;
  std::unique_ptr<detail::KeepRun> keep_run_;  // the run of held steps not written yet

  void put(const std::string& text);
};

/// Reads a session file; throws SessionFileError naming the file and line of what is wrong (a
/// damaged line, a file cut short unless read up to its last whole record, another version).
Session read_session(const std::string& path, SessionRead read = SessionRead::Whole);
/// The same for a session's text already read; errors name `path`.
Session parse_session(const std::string& text, const std::string& path,
                      SessionRead read = SessionRead::Whole);
/// Writes a whole session (e.g. one with a command changed).
void write_session(const std::string& path, const Session& session);

/// How a replay ended.
struct ReplayOutcome {
  bool equal = true;   ///< every recorded hash was met
  uint64_t steps = 0;  ///< steps replayed
  std::size_t hashes_checked = 0;
  std::size_t commands_run = 0;
  /// The first step whose hash differs, the last one that was equal, and both hashes.
  std::optional<uint64_t> first_difference;
  uint64_t last_equal = 0;
  uint64_t recorded_hash = 0, replayed_hash = 0;
  std::string message;  ///< one paragraph saying what happened
};

/// What parses the world a recorded load names (as the simulator did); an empty function when
/// `command` is no load.
using SessionWorldLoader = std::function<std::function<WorldSpec()>(const Command& command)>;

/// The typed request of a server's request a session recorded (`recorded` carries it as a
/// WireRequest: its name and bytes), as its server would have queued it; nullptr when its bytes
/// are not one.
using RequestReader = std::function<std::shared_ptr<const Request>(const Command& recorded)>;

/// Replays a session on a runner built from its header's world, with the executors of its
/// sources set (the same as a live run's, minus the answers): runs each command at its step
/// (a robot command's sender noted as arrived: Runner::note_arrival()),
/// steps, checks each recorded hash, and stops at the first that differs. Each embedded file
/// goes into `files` (what the runner's data roots read) before the first command recorded
/// after it. `after_step` runs after each step it takes (e.g. a resumed simulator's robots
/// read what the step made). `read` makes each server's request typed before it runs; one
/// it cannot read ends the replay there, naming the command.
ReplayOutcome replay_session(const Session& session, Runner& runner, const SessionWorldLoader& load,
                             MemoryFiles* files = nullptr,
                             const std::function<void()>& after_step = {},
                             const RequestReader& read = {});
/// Puts the files the session embeds before its first command into `files` (what its first
/// world is read from).
void embed_first_files(const Session& session, MemoryFiles& files);
/// The checksum an embedded file carries (64-bit XXH3 of its bytes).
uint64_t file_checksum(const std::string& bytes);

}  // namespace macsim
