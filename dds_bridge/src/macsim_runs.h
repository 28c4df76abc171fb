// The three ways macsim runs a world once it is loaded: served over DDS until stopped, a
// recorded session replayed, or views rendered offscreen to files.
#pragma once

#include <string>
#include <vector>

#include "macsim/render/renderer.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/session.h"
#include "macsim_options.h"

namespace macsim::program {

/// Serves the runner's world over DDS until SIGINT/SIGTERM or --duration, recording to
/// `session` if there is one; the exit code.
int serve(macsim::Runner& runner, const Options& o, const macsim::SessionWriter* session);

/// Replays the recorded session of `o` on `runner` (its world): no DDS, the commands at their
/// steps; 0 when every hash matched.
int replay(macsim::Runner& runner, const Options& o);

/// --snapshot: settles, renders each requested camera mode offscreen, writes the PNGs.
int write_snapshots(macsim::Runner& runner, const std::vector<std::string>& requests, double settle,
                    const macsim::render::CameraIntrinsics& intrinsics);

}  // namespace macsim::program
