// The final demonstrator's controller: finds cans with its cameras, lifts one with the crane's
// magnet, drops it on the door's floor switch, sees the door open with its laser and drives
// through. Its four scenes are calls to the affordance library's behaviours
// (macsim/affordances/behaviours.h), which decide from the robot's own topics only (odometry, IMU,
// stereo images, laser clouds, crane state), so the same program drives the simulated and the
// real KURT3D.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "macsim/affordances/behaviours.h"
#include "macsim/affordances/model.h"

namespace kurt_demo {

/// Exit codes: one per way the scenario can fail.
enum Exit : int {
  kThrough = 0,
  kUsage = 2,
  kNoRobot = 3,
  kNoCan = 4,
  kNoLiftableCan = 5,
  kDoorClosed = 6,
  kTimeout = 7,
  kNoSwitch = 8,
  kNoPassage = 9,
};

/// A failure of the scenario: the exit code and why.
struct Failure {
  Exit code;
  std::string reason;
};

struct DemoOptions {
  macsim::affordances::LoopOptions loop;  ///< robot, lock-step, timeouts (400 s of robot time)
  bool pictures = false;         ///< ask the simulator for an overview picture per scene
  std::string debug_images;      ///< folder for the camera images with what was seen, or empty
  /// A lift model (affordance_learn --save-model) to rank the cans by before trying any.
  std::optional<macsim::affordances::AffordanceModel> lift_model;
};

/// The lift model in DIR/lift.yml, if its features are ones the demonstrator computes from where
/// it stands (the cameras': colour, blob shape, stereo size); throws Failure{kUsage} naming the
/// file and what is wrong.
macsim::affordances::AffordanceModel load_lift_model(const std::string& dir);

class DemoController : public macsim::affordances::Behaviours {
 public:
  DemoController(macsim::dds::Participant& participant, const DemoOptions& options);
  ~DemoController() override;
  /// Plays the scenario; returns when the robot is through the door or throws Failure (or
  /// macsim::affordances::LoopError: no robot, timeout, no cloud).
  void run();

 private:
  /// Scene 2: the cans in turn (with a lift model, the likeliest to come up first; then the
  /// nearest, colours that failed last) until one comes up.
  void lift_a_can();

  DemoOptions options_;
  std::vector<std::string> failed_colours_;
};

}  // namespace kurt_demo
