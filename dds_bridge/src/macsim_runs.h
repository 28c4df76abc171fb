// The three ways macsim runs a world once it is loaded: served over DDS until stopped, a
// recorded session replayed, or views rendered offscreen to files.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "macsim/msg/macsim_msgs.h"
#include "macsim/render/renderer.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/session.h"
#include "macsim_options.h"

namespace macsim {
class SimBridge;
}

namespace macsim::program {

/// What a resumed run carries on from: the replies sent before the kill, the requests taken
/// and answered.
struct Resumed {
  std::vector<macsim_msgs::msg::dds_::SupervisorReply_> supervisor_replies;
  std::vector<macsim::RecordedRequest> requests;
  /// Runs the session up to where the killed process left it, once the robots' topics exist
  /// and before anything is served (each step given to the bridge: SimBridge::replayed_step()),
  /// and sets `writer` to record on; 0 to go on, else the exit code.
  std::function<int(macsim::SimBridge&)> catch_up;
  std::shared_ptr<macsim::SessionWriter> writer;
};

/// Serves the runner's world over DDS until SIGINT/SIGTERM or --duration, recording to
/// `session` if there is one (and carrying on from `resumed` if given: its catch-up first, and
/// its writer then records); the exit code.
int serve(macsim::Runner& runner, const Options& o, const macsim::SessionWriter* session,
          Resumed* resumed = nullptr);

/// --resume: runs the session of `o` on `runner` (its world) to its last whole record, checking
/// every hash, then serves on, recording on to the same file; the exit code.
int resume(macsim::Runner& runner, const Options& o);

/// Replays the recorded session of `o` on `runner` (its world): no DDS, the commands at their
/// steps; 0 when every hash matched.
int replay(macsim::Runner& runner, const Options& o);

/// --snapshot: settles, renders each requested camera mode offscreen, writes the PNGs.
int write_snapshots(macsim::Runner& runner, const std::vector<std::string>& requests, double settle,
                    const macsim::render::CameraIntrinsics& intrinsics);

}  // namespace macsim::program
