// One robot node: serves any RobotInterface on rt/<robot>/* (the topics of what it has), for
// the simulator and the real robot's adapter alike. Reader callbacks only hand commands to the
// owner's queue; the owner runs them and calls publish() on its own thread.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/robot/robot_interface.h"

namespace macsim::robot {

/// Hands a command (robot_command.h) to the owner's queue (called on Fast DDS's threads), with
/// who sent it; the owner gives it to the robot on its own thread (RobotInterface::execute).
using PostCommand = std::function<void(RobotCommand, const dds::SampleId& sent)>;

/// How a node names its frames and takes its commands.
struct NodeOptions {
  /// Before every frame id it publishes ("kurt/": kurt/odom, kurt/base_link), so several robots
  /// share one TF tree.
  std::string frame_prefix;
  /// cmd_vel as geometry_msgs/TwistStamped instead of Twist (Nav2 from ROS 2 Kilted on).
  bool cmd_vel_stamped = false;
  /// The QoS family of its sensor writers (ranges, scans, clouds): LockstepSensor for a
  /// lock-step simulator, whose samples are sent once each.
  dds::QosFamily sensors = dds::QosFamily::Sensor;
  /// Told of each command sample dropped (a number not finite, or numbers that do not fit):
  /// it arrived, and does nothing (a lock-step simulator's step request waits for no more).
  std::function<void(const dds::SampleId& sent)> dropped;
};

/// Serves one robot over DDS.
class RobotNode {
 public:
  /// Creates the writers and readers of what `robot` has, a plug-in's own commands included
  /// (Capabilities::commands: rt/<robot>/command/<name>). Commands with a number that is not
  /// finite, or numbers that do not fit their command, are dropped; the rest go to `post`.
  /// Throws std::invalid_argument for a declared command that no command type registers.
  RobotNode(dds::Participant& participant, RobotInterface& robot, PostCommand post,
            NodeOptions options = {});
  ~RobotNode();
  RobotNode(const RobotNode&) = delete;
  RobotNode& operator=(const RobotNode&) = delete;

  /// Hands over every command the readers hold (call right before the robot acts on them).
  void poll_commands();
  /// Reads the robot and writes what is new (the owner's thread): its topics, the moving frames
  /// on rt/tf (odom -> base_footprint, the rotating laser, the crane) and, the first time, the
  /// fixed ones on rt/tf_static.
  /// `hold`: nothing is written yet; only the newest message of each kind waits for flush()
  /// (lock-step: a controller reads only at the end of its step request).
  void publish(bool hold = false);
  /// Writes what publish(true) held back; the names of the topics it wrote go to `written`
  /// (if given), in that order.
  void flush(std::vector<std::string>* written = nullptr);
  /// Reads the robot into latest() and writes nothing: what it has went out already (a
  /// simulator resumed from a session, the killed process having published it).
  void prime();
  /// The newest of each reading published (or held) so far.
  const Readings& latest() const { return latest_; }
  /// "topic (type, in|out)" of each topic served.
  std::vector<std::string> topic_lines() const;
  /// The topics a full KURT3D serves that this robot lacks.
  std::vector<std::string> lacking_topics() const;

 private:
  struct Topics;
  struct Outbox;
  struct Held;
  /// Makes the messages of `readings` (what is in them) into the outbox.
  void fill(const Readings& readings);
  /// Keeps the newest of each kind of `readings` in latest().
  void remember(const Readings& readings);
  RobotInterface& robot_;
  NodeOptions options_;
  Frames frames_;
  bool static_sent_ = false;
  Readings latest_;
  std::unique_ptr<Topics> topics_;
  std::unique_ptr<Outbox> outbox_;
  std::unique_ptr<Held> held_;
};

}  // namespace macsim::robot
