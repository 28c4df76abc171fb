// macsim's command line: what it asks for (Options), read from argv (parse_options()), and
// what follows from it: the folders requests may name files in, a line on the world loaded.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/render/renderer.h"
#include "macsim/sim_core/data_roots.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/session.h"
#include "macsim/sim_core/snapshot_store.h"
#include "macsim/sim_core/world_bounds.h"
#include "macsim/sim_core/world_loader.h"
#include "pictures/picture_server.h"

namespace macsim::program {

/// What the command line asks for.
struct Options {
  std::string world_file;
  macsim::dds::ParticipantOptions participant{0, "", "macsim"};
  double rtf = 1.0;
  double duration = 0.0;
  bool as_fast_as_possible = false;
  bool realtime = false;
  bool validate = false;
  bool strict = false;
  bool keep_overlaps = false;
  bool paused = false;
  bool lockstep = false;
  double status_period = 0.0;
  std::vector<std::string> snapshots;
  double settle = 1.0;
  macsim::render::CameraIntrinsics snapshot_size{640, 480};
  std::string pictures;
  int seed = -1;
  std::string cameras = "320x240";
  double camera_rate = 15.0;
  bool robot_frames = false;
  bool cmd_vel_stamped = false;
  bool viewer = false;
  std::string camera_mode = "MouseKeyboard";
  std::string viewer_screenshot;
  int max_objects = int(macsim::bounds::kMaxObjects);
  int max_import_depth = int(macsim::bounds::kMaxImportDepth);
  int max_imported_files = int(macsim::bounds::kMaxImportedFiles);
  int max_snapshots = int(macsim::SnapshotLimits{}.max_count);
  std::string max_snapshot_bytes = std::to_string(macsim::SnapshotLimits{}.max_bytes);
  int max_pictures = int(macsim::PictureServer::kDefaultMaxFiles);
  int max_queued_commands = int(macsim::kDefaultMaxQueuedCommands);
  double command_wait = macsim::kDefaultCommandWait;  // s
  macsim::SnapshotLimits snapshot_limits;             // from the two above, once parsed
  std::vector<std::string> data_paths;
  std::string record_session;
  int session_hash_every = 100;
  std::string replay;
  std::string extract;                     // --replay FILE --extract DIR
  std::string compare;                     // --compare A B: A
  std::vector<std::string> arguments;      // B of --compare A B
  std::string resume;                      // --resume FILE
  int kill_at_step = 0;                    // --kill-at-step N (tests of --resume): 0 never
  std::optional<macsim::Session> session;  // read from --replay, or from --resume if it exists
  /// The files a self-contained session holds (--replay): all a replay reads.
  std::shared_ptr<macsim::MemoryFiles> session_files;

  macsim::LoadLimits limits() const {
    return {std::size_t(max_import_depth), std::size_t(max_imported_files),
            std::size_t(max_objects)};
  }
};

/// Reads the command line into `o`; an exit code if the program should exit now (--help, a bad
/// option).
std::optional<int> parse_options(int argc, char** argv, Options& o);

/// The folders requests may name files in: the world's, the shipped worlds, each --data-path;
/// in a replay of a self-contained session, its files only.
std::shared_ptr<const macsim::DataRoots> data_roots(const Options& o);
/// Where the first world is read from: the disk, or a replayed session's files.
const macsim::WorldFiles& world_files(const Options& o);
/// The session header a recording of this run starts with.
macsim::SessionHeader session_header(const Options& o, bool overlaps_parted);
/// --extract: writes the session's files under `dir` (their paths made relative), one line
/// each; 0, or 2 when one cannot be written.
int extract_session_files(const macsim::Session& session, const std::string& dir);

/// One line on what the world holds.
std::string world_summary(const macsim::WorldSpec& spec);

}  // namespace macsim::program
