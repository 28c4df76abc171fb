// The final demonstrator's controller: finds cans with its cameras, lifts one with the crane's
// magnet, drops it on the door's floor switch, sees the door open with its laser and drives
// through. It decides from the robot's own topics only (odometry, IMU, stereo images, laser
// clouds, crane state), so the same program drives the simulated and the real KURT3D.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "kurt_geometry.h"
#include "laser_map.h"
#include "macsim/affordances/model.h"
#include "robot_loop.h"
#include "vision.h"

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
  kurt_loop::LoopOptions loop;   ///< robot, lock-step, timeouts (400 s of robot time)
  bool pictures = false;         ///< ask the simulator for an overview picture per scene
  std::string debug_images;      ///< folder for the camera images with what was seen, or empty
  /// A lift model (affordance_learn --save-model) to rank the cans by before trying any.
  std::optional<macsim::affordances::AffordanceModel> lift_model;
};

/// The lift model in DIR/lift.yml, if its features are ones the demonstrator computes from where
/// it stands (the cameras': colour, blob shape, stereo size); throws Failure{kUsage} naming the
/// file and what is wrong.
macsim::affordances::AffordanceModel load_lift_model(const std::string& dir);

using kurt_loop::Pose2;

/// A can candidate in the odometry frame.
struct Candidate {
  double x = 0, y = 0;
  std::string colour;
  int seen = 0;
  bool tried = false;
  std::string outcome;
  double liftable = 0;  ///< the lift model's mean probability of `liftable` over the sightings
  int judged = 0;       ///< sightings the model judged
};

class DemoController : public kurt_loop::RobotLoop {
 public:
  DemoController(macsim::dds::Participant& participant, const DemoOptions& options);
  ~DemoController() override;
  /// Plays the scenario; returns when the robot is through the door or throws Failure (or
  /// kurt_loop::LoopError: no robot, timeout, no cloud).
  void run();
  /// Cans the crane tried to lift so far.
  int lift_attempts() const { return lift_attempts_; }

 private:
  // ---- the loop ---------------------------------------------------------------------------
  void say(const std::string& scene, const std::string& text);
  void picture(const std::string& name);

  // ---- motion -----------------------------------------------------------------------------
  void park_crane();
  /// Lowers the magnet at `lift` onto something whose top is `height` above the floor: fast
  /// to just above it, then slowly until the magnet holds something (`until_held`) or rests.
  /// What the magnet holds, if anything.
  std::string lower_onto(double lift, double height, bool until_held);

  // ---- sensing ----------------------------------------------------------------------------
  /// Stops, lets the robot settle, and returns what `frames` stereo pairs show, in odometry.
  std::vector<std::pair<Sighting, Pose2>> look(int frames = 1);
  void record(const std::vector<std::pair<Sighting, Pose2>>& sightings);
  /// Stops, takes a laser cloud and adds it to the obstacle map.
  void map_here();
  /// Where to stand `standoff` from `target` so that the robot fits there and the straight
  /// way in (to `reach` from it) is free; the direction from the robot first.
  Point approach_point(Point target, double standoff, double reach) const;
  /// Drives to `goal` in straight lines, around what the map shows in the way.
  void travel_to(Point goal, double tolerance);

  // ---- scenes -----------------------------------------------------------------------------
  void search(const std::string& scene, bool want_switch);
  /// Looks for `target` again where it should be (and a little to each side): where it is.
  std::optional<Point> find_again(const Candidate& target, Kind kind);
  /// Walks up to `target` (standing off, looking again, updating it) and drives in until it is
  /// at the crane's reach ahead; false if it is no longer to be seen.
  bool close_in(Candidate& target, Kind kind);
  bool try_lift(Candidate& can);
  void deliver();
  void go_through();

  DemoOptions options_;
  KurtGeometry geometry_;
  struct Pictures;
  std::unique_ptr<Pictures> pictures_;

  // what the robot knows
  std::vector<Candidate> candidates_;
  std::optional<Candidate> switch_;
  std::vector<std::string> failed_colours_;
  int lift_attempts_ = 0;
  ObstacleMap obstacles_;
  int debug_count_ = 0;
};

}  // namespace kurt_demo
