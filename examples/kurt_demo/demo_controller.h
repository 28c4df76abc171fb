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
#include "macsim/client/robot_client.h"
#include "macsim/client/robot_devices.h"
#include "macsim/client/supervisor_client.h"
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
  std::string robot = "kurt";
  bool lockstep = false;         ///< step the simulation (SIM_STEP) instead of following it
  double timeout = 400.0;        ///< s of robot time for the whole scenario
  double discovery_timeout = 20.0;  ///< s of wall time to find the robot
  bool pictures = false;         ///< ask the simulator for an overview picture per scene
  std::string debug_images;      ///< folder for the camera images with what was seen, or empty
  /// A lift model (affordance_learn --save-model) to rank the cans by before trying any.
  std::optional<macsim::affordances::AffordanceModel> lift_model;
};

/// The lift model in DIR/lift.yml, if its features are ones the demonstrator computes from where
/// it stands (the cameras': colour, blob shape, stereo size); throws Failure{kUsage} naming the
/// file and what is wrong.
macsim::affordances::AffordanceModel load_lift_model(const std::string& dir);

/// A planar pose in the odometry frame.
struct Pose2 {
  double x = 0, y = 0, yaw = 0;
};

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

class DemoController {
 public:
  DemoController(macsim::dds::Participant& participant, const DemoOptions& options);
  ~DemoController();
  /// Plays the scenario; returns when the robot is through the door or throws Failure.
  void run();
  /// Robot time since the start, s.
  double elapsed() const { return now_ - start_; }
  /// Cans the crane tried to lift so far.
  int lift_attempts() const { return lift_attempts_; }

 private:
  // ---- the loop ---------------------------------------------------------------------------
  void connect();
  /// Sends the current set-points, lets `seconds` of robot time pass, reads odometry and IMU.
  void tick(double seconds = 0.05);
  void wait(double seconds);
  void say(const std::string& scene, const std::string& text);
  void picture(const std::string& name);

  // ---- motion -----------------------------------------------------------------------------
  void turn_to(double yaw);
  void drive_to(double x, double y, double tolerance, double speed = 0.3);
  void drive_straight(double distance, double speed);
  /// Moves the crane to the targets and waits until it is there (or `timeout` passed).
  bool crane_to(double slew, double lift, double hoist, double timeout = 4.0);
  void park_crane();
  /// Lowers the magnet at `lift` onto something whose top is `height` above the floor: fast
  /// to just above it, then slowly until the magnet holds something (`until_held`) or rests.
  /// What the magnet holds, if anything.
  std::string lower_onto(double lift, double height, bool until_held);

  // ---- sensing ----------------------------------------------------------------------------
  /// Stops, lets the robot settle, and returns what `frames` stereo pairs show, in odometry.
  std::vector<std::pair<Sighting, Pose2>> look(int frames = 1);
  /// Stops and returns a laser cloud taken wholly after stopping.
  macsim::client::Cloud take_cloud();
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

  Pose2 to_odom(double bx, double by) const;
  Pose2 to_base(double x, double y) const;

  DemoOptions options_;
  KurtGeometry geometry_;
  macsim::dds::Participant& participant_;
  macsim::client::RobotClient drive_;
  macsim::client::Crane crane_;
  macsim::client::StereoCamera cameras_;
  macsim::client::Laser laser_;
  macsim::client::Imu imu_;
  std::unique_ptr<macsim::client::SimulationClient> simulation_;  // lock-step only
  struct Pictures;
  std::unique_ptr<Pictures> pictures_;
  double step_size_ = 0.001;

  // set-points, sent with every tick
  double linear_ = 0, angular_ = 0;
  double slew_ = 0, lift_ = 0, hoist_ = 0;
  bool magnet_ = false;
  double rotunit_ = 0;

  // what the robot knows
  double now_ = 0, start_ = 0;
  Pose2 pose_;
  std::optional<std::pair<double, double>> last_position_;  // odometry's, for the distance
  std::vector<Candidate> candidates_;
  std::optional<Candidate> switch_;
  std::vector<std::string> failed_colours_;
  int lift_attempts_ = 0;
  bool looking_ = false;  // lock-step: the cameras render only while looking
  ObstacleMap obstacles_;
  int debug_count_ = 0;
};

}  // namespace kurt_demo
