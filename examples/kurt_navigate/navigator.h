// kurt_navigate's controller: drives the KURT3D to a goal through clutter from its own 3D laser.
// At each stop it takes one cloud, groups its returns above the floor into things, judges each
// thing, plans the shortest way to the goal over the floor and what it judged traversable, drives
// a stretch of it, and looks again. Its judgement is a learned traverse model, asked about each
// thing as a trial saw its obstacle (policy "model": into what rolls away, over what is low,
// around the rest), or the baseline (policy "avoid": clear of every return above the floor).
#pragma once

#include <map>
#include <optional>
#include <string>

#include "macsim/affordances/model.h"
#include "macsim/affordances/traverse.h"
#include "macsim/affordances/robot_loop.h"
#include "ways.h"

namespace kurt_navigate {

using macsim::affordances::FloorPlan;
using macsim::affordances::Height;
using macsim::affordances::Thing;

/// Exit codes.
enum Exit : int {
  kAtGoal = 0,
  kUsage = 2,
  kNoRobot = 3,
  kNoWay = 4,  ///< no way judged passable from where it stands
  kTimeout = 7,
  kNoCloud = 9,
};

enum class Policy { Model, Avoid };

struct NavigateOptions {
  macsim::affordances::LoopOptions loop;        ///< robot, lock-step, timeouts
  double goal_x = 6.0, goal_y = 0.0;  ///< m, odometry frame
  double tolerance = 0.3;             ///< m from the goal that counts as there
  Policy policy = Policy::Model;
  std::optional<macsim::affordances::AffordanceModel> traverse_model;  ///< Policy::Model
  bool verbose = false;  ///< print each look's odometry fit and things
};

/// What a run did.
struct Outcome {
  Exit code = kAtGoal;
  std::string reason;
  int stretches = 0, stalls = 0;
  Sightings::Counts things;
};

class Navigator : public macsim::affordances::RobotLoop {
 public:
  Navigator(macsim::dds::Participant& participant, const NavigateOptions& options);
  /// Drives to the goal; the outcome says whether it got there (or why not: no robot, no way,
  /// timeout, no cloud) and what it met on the way.
  Outcome run();

 private:
  /// Where to stand to judge a thing: its middle (odometry frame) and its near side, m from the
  /// robot along the bearing of its middle.
  struct Stand {
    Point2 centre{};
    double near = 0;
  };
  struct Way {
    std::vector<Point2> points;  ///< from the robot to the goal; empty when there is none
    double stretch = 0;          ///< m to drive before looking again
    std::optional<Stand> judge;  ///< first stand before this thing, to judge it
  };
  /// `cloud` (base_link) levelled by the IMU's roll and pitch: a robot standing on a joist or a
  /// log sees the floor and what stands on it at their heights.
  macsim::client::Cloud level(macsim::client::Cloud cloud) const;
  /// The way to the goal from here, judged from `cloud`.
  Way plan(const macsim::client::Cloud& cloud);
  /// Turns to face the thing and moves to stand where a trial stood before its obstacle (its
  /// near side kTrialNear ahead).
  void stand_before(const Stand& stand);
  /// A stall (`why`): counted, what it stood against marked as blocking, and 0.3 m backed off.
  void back_off(Outcome& out, const std::string& why);
  /// Follows `way` for `stretch` m (or to its end); false when it stalled (its wheels made no
  /// 2 cm in a second).
  bool follow(const std::vector<Point2>& way, double stretch);
  /// The run itself; throws macsim::affordances::LoopError.
  void drive(Outcome& out);
  void say(const std::string& text);
  void after_tick() override;

  NavigateOptions options_;
  Sightings sightings_;
  std::vector<Point2> pressed_;  // odometry frame: where it stalled against something
  /// A thing's judgement, kept per 5 cm cell it covered: P(traversable), and how far the look
  /// it came from stood from a trial's (|near side - the trials'|, m): a nearer look replaces it.
  struct Verdict {
    double p_traversable = 0, off_trial = 0;
  };
  std::map<std::pair<int, int>, Verdict> verdicts_;
};

}  // namespace kurt_navigate
