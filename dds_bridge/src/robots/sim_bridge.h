// Maps one Runner onto DDS topics: commands in (queued), clock and robot data out.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/msg/rosgraph_msgs.h"
#include "macsim/render/renderer.h"
#include "macsim/robot/robot_interface.h"
#include "macsim/sim_core/runner.h"
#include "robots/schedule.h"

namespace macsim {

/// What the bridge serves besides the robots' basic topics.
struct BridgeOptions {
  bool cameras = true;              ///< render and publish the stereo cameras
  render::CameraIntrinsics camera;  ///< their image size and field of view
  double camera_rate = 15.0;        ///< Hz of sim time
  bool robot_frames = false;        ///< frame ids start with "<robot>/" (several robots, one tree)
  bool cmd_vel_stamped = false;     ///< cmd_vel as geometry_msgs/TwistStamped
  bool lockstep = false;            ///< sensor data sent reliably (QosFamily::LockstepSensor)
  /// A resumed simulator replays its session first: robot commands that come meanwhile wait
  /// for caught_up().
  bool replaying = false;
};

/// Serves a runner's world over DDS. Reader callbacks only push commands onto the runner's
/// queue; publish() runs on the simulation thread after each step. Camera images are rendered
/// and published on a thread of their own from copies of the scene.
class SimBridge {
 public:
  SimBridge(dds::Participant& participant, Runner& runner, const BridgeOptions& options);
  ~SimBridge();

  /// Queues every robot command already received (call right before a step: a command its
  /// writer saw acknowledged before asking for the step lands in that step, in lock-step too).
  void poll_commands();
  /// Publishes what the last step produced (clock, odometry, sensors; cameras handed over).
  /// During a step request that wants its data at its end, only the newest of each is kept.
  void publish();
  /// Writes what publish() kept back (a step request's end).
  void flush();
  /// The topics the last flush() wrote, in the order written (a step request's reply names them).
  const std::vector<std::string>& flushed() const { return flushed_; }
  /// A step a resumed simulator replayed from its session, before serving (the steps of the
  /// run the killed process made). `held`: inside a step request that wanted its data at its
  /// end, which the killed process kept back and never wrote: what the robots read is kept
  /// back again, the newest of each with the stamp it had, for that request's end. Otherwise
  /// what they read went out with the killed process (replayed_as_sent()).
  void replayed_step(bool held);
  /// What the robots read in the steps replayed so far and not held went out with the killed
  /// process: taken as read, sent no more (call after the step before a held request's first).
  void replayed_as_sent();
  /// The replay is over: replayed_as_sent(), and the robot commands that came meanwhile go to
  /// the runner, in the order they came (BridgeOptions::replaying).
  void caught_up();
  /// The newest readings a robot published (empty name: the first robot), or nullptr.
  const robot::Readings* latest_readings(const std::string& robot) const;
  /// Blocks until every camera image submitted so far is rendered and written (lock-step: the
  /// step is done when its data is out, and which instants are rendered does not depend on
  /// timing).
  void wait_for_cameras();
  /// One line per robot with cameras: stereo frames rendered and dropped (renderer busy).
  std::string camera_summary() const;
  /// One line per robot whose commands were dropped because the runner's queue was full.
  std::string command_summary() const;
  /// Topic names this bridge serves, for the start-up banner.
  std::vector<std::string> topic_names() const;

 private:
  struct RobotTopics;
  struct Gate;
  void publish_cameras(RobotTopics& topics, double now, bool render);
  void flush_clock();
  /// publish(); `replayed`: a held step replayed (replayed_step()): kept back, nothing rendered.
  void publish_step(bool replayed);

  Runner& runner_;
  BridgeOptions options_;
  Schedule clock_instants_{100.0};  // /clock at 100 Hz of sim time
  bool started_ = false;            // the schedules run
  std::optional<rosgraph_msgs::msg::dds_::Clock_> held_clock_;
  uint64_t generation_ = 0;           // of the world whose schedules run
  uint64_t time_origins_ = 0;         // World::time_origin().count the schedules started at
  std::vector<std::string> flushed_;  // by the last flush()
  bool replayed_unread_ = false;  // steps were replayed whose readings went out with the killed run
  struct Clock;
  std::unique_ptr<Clock> clock_;
  std::unique_ptr<Gate> gate_;  // before robots_: their commands' callbacks use it
  std::vector<std::unique_ptr<RobotTopics>> robots_;
};

}  // namespace macsim
