// Trials spread over K lock-step simulators: started here (one macsim per DDS domain) or
// attached to (already running, on this host or another). Each instance has a worker that takes
// the next trial. A simulator started here that stops answering is connected to again while its
// process runs and started again when it died (its trial played again from its reset); an
// instance lost for good is dropped and its trial goes to another.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "trial_record.h"
#include "trial_robot.h"

namespace affordances {

struct PoolOptions {
  int instances = 1;        ///< simulators to start
  int first_domain = -1;    ///< the first one's domain; the others follow
  std::vector<int> attach;  ///< domains of running simulators to use instead
  std::string world;        ///< world file for the simulators started here
  std::string cameras = "320x240";
  std::string log_dir;       ///< where the started simulators' logs go
  InstanceOptions instance;  ///< profile, robot, camera rate, timeouts (domain set per instance)
};

/// What a run came to.
struct PoolSummary {
  int done = 0;
  int lost_instances = 0;
  int reconnects = 0;              ///< to simulators of this run lost while still running
  int restarts = 0;                ///< simulators of this run started again after they died
  int failed = 0;                  ///< trials refused by the simulator (not retried)
  std::vector<TrialSpec> not_run;  ///< every instance was lost before these ran
};

class TrialPool {
 public:
  explicit TrialPool(PoolOptions options) : options_(std::move(options)) {}
  /// Runs every trial; `done` is called for each finished one, one call at a time. Messages
  /// (an instance lost, a trial refused) go to stderr.
  PoolSummary run(const std::vector<TrialSpec>& trials,
                  const std::function<void(const TrialRecord&)>& done);

 private:
  PoolOptions options_;
};

}  // namespace affordances
