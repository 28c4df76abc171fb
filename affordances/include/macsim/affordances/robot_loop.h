// The loop a KURT3D controller runs on the robot's own topics: its set-points sent every tick,
// robot time passing (stepping a lock-step simulator, or following the robot), odometry and IMU
// read into a pose; and the motions and the sensing built on it. The same loop drives macsim
// and the real robot (kurt_adapter). kurt_demo and kurt_navigate are made of it.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "macsim/client/robot_client.h"
#include "macsim/client/robot_devices.h"
#include "macsim/client/supervisor_client.h"
#include "macsim/dds/command_line.h"
#include "macsim/robot/kurt3d_description.h"

namespace macsim::affordances {

/// Why the loop cannot go on.
enum class Stop { NoRobot, Timeout, NoCloud };

/// The loop stopped: the robot is gone, the robot time is up, or the laser gave no cloud.
struct LoopError : std::runtime_error {
  LoopError(Stop why, const std::string& what) : std::runtime_error(what), stop(why) {}
  Stop stop;
};

struct LoopOptions {
  std::string robot = "kurt";
  bool lockstep = false;            ///< step the simulation (SIM_STEP) instead of following it
  double timeout = 400.0;           ///< s of robot time for the whole run
  double discovery_timeout = 20.0;  ///< s of wall time to find the robot
  /// s of wall time to wait for a simulator that went away (killed, restarting: macsim
  /// --resume) or a robot gone silent, before giving up; 0: give up at once.
  double restart_patience = 120.0;
};

/// The loop's options on a controller's command line: --robot, --lockstep, --timeout,
/// --discovery-timeout, --restart-patience (their defaults from `options`).
void add_loop_options(macsim::dds::CommandLine& cli, LoopOptions& options);
/// What is wrong with the options (a timeout not positive, an empty robot name), or empty.
std::string loop_options_problem(const LoopOptions& options);

/// A planar pose in the odometry frame.
struct Pose2 {
  double x = 0, y = 0, yaw = 0;
};

/// An angle in (-pi, pi].
double wrap(double a);

/// A controller's loop and motions; a program derives from it and adds its scenario.
class RobotLoop {
 public:
  RobotLoop(macsim::dds::Participant& participant, const LoopOptions& options);
  virtual ~RobotLoop();
  /// Robot time since connect(), s.
  double elapsed() const { return now_ - start_; }

 protected:
  static constexpr double kTick = 0.05;  ///< s of robot time per control step

  /// Sends the current set-points (drive, crane, magnet, laser); in lock-step, until delivered.
  void send_set_points();
  /// Finds the robot (and the lock-step simulator): its odometry, IMU and crane.
  void connect();
  /// Sends the current set-points, lets `seconds` of robot time pass, reads odometry and IMU.
  void tick(double seconds = kTick);
  void wait(double seconds);
  /// Turns on the spot to `yaw` (odometry frame).
  void turn_to(double yaw);
  /// Turns towards (x, y), then drives there, steering.
  void drive_to(double x, double y, double tolerance, double speed = 0.3);
  /// Drives `distance` (negative: backwards) holding the heading it had; stops early when it
  /// made no `stall_progress` m of headway in `stall_time` s (0: never) and returns false.
  bool drive_straight(double distance, double speed, double stall_time = 0,
                      double stall_progress = 0.02);
  /// Moves the crane to the targets and waits until it is there (or `timeout` passed).
  bool crane_to(double slew, double lift, double hoist, double timeout = 4.0);
  /// Stops and returns a laser cloud taken wholly after stopping (the rotating unit turning at
  /// `rotunit_`, which must not be 0).
  macsim::client::Cloud take_cloud();

  /// Called at the end of every tick, the pose updated (e.g. to keep the path).
  virtual void after_tick() {}

  /// A point given in base_link, in the odometry frame; and back.
  Pose2 to_odom(double bx, double by) const;
  Pose2 to_base(double x, double y) const;

  LoopOptions loop_options_;
  macsim::client::RobotClient drive_;
  macsim::client::Crane crane_;
  macsim::client::StereoCamera cameras_;
  macsim::client::Laser laser_;
  macsim::client::Imu imu_;
  std::unique_ptr<macsim::client::SimulationClient> simulation_;  // lock-step only
  double step_size_ = 0.001;

  // set-points, sent with every tick
  double linear_ = 0, angular_ = 0;
  double slew_ = 0, lift_ = 0, hoist_ = 0;
  bool magnet_ = false;
  double rotunit_ = 0;
  bool looking_ = false;  ///< lock-step: the cameras render only while this is set

  // where the robot is
  double now_ = 0, start_ = 0;
  Pose2 pose_;

 private:
  std::optional<std::pair<double, double>> last_position_;  // odometry's, for the distance
  /// Writers each data reader matched so far (odometry, IMU, cameras, laser, crane state), and
  /// readers each command writer matched (drive, crane and magnet, rotating unit).
  using PeersSeen = std::array<int, 8>;
  PeersSeen peers_seen() const;
  /// True once every endpoint that had a peer at the last tick matched a new one (the
  /// simulator restarted: its endpoints are new).
  bool simulator_renewed() const;
  PeersSeen peers_seen_{};  // peers_seen() at the last tick
};

}  // namespace macsim::affordances
