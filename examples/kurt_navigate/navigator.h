// kurt_navigate's controller: drives the KURT3D to a goal through clutter from its own 3D laser.
// At each stop it takes one cloud, judges the ways it could take (every 15 degrees around the
// goal's bearing), drives a stretch of the way nearest the goal that it judges traversable, and
// looks again. Its judgement is a learned traverse model (policy "model": into what rolls away,
// over what is low, around the rest) or the baseline (policy "avoid": clear of every return
// above the floor).
#pragma once

#include <optional>
#include <string>

#include "macsim/affordances/model.h"
#include "robot_loop.h"
#include "ways.h"

namespace kurt_navigate {

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
  kurt_loop::LoopOptions loop;        ///< robot, lock-step, timeouts
  double goal_x = 6.0, goal_y = 0.0;  ///< m, odometry frame
  double tolerance = 0.3;             ///< m from the goal that counts as there
  Policy policy = Policy::Model;
  std::optional<macsim::affordances::AffordanceModel> traverse_model;  ///< Policy::Model
};

/// What a run did.
struct Outcome {
  Exit code = kAtGoal;
  std::string reason;
  int stretches = 0, stalls = 0;
  Sightings::Counts things;
};

class Navigator : public kurt_loop::RobotLoop {
 public:
  Navigator(macsim::dds::Participant& participant, const NavigateOptions& options);
  /// Drives to the goal; the outcome says whether it got there (or why not: no robot, no way,
  /// timeout, no cloud) and what it met on the way.
  Outcome run();

 private:
  struct Choice {
    double heading = 0;  ///< odometry frame
    double score = 0;    ///< model: P(traversable); avoid: free length, m
    bool passable = false;
  };
  /// The way to take from here, judged from `cloud`.
  std::optional<Choice> choose(const macsim::client::Cloud& cloud);
  /// The run itself; throws kurt_loop::LoopError.
  void drive(Outcome& out);
  void say(const std::string& text);
  void after_tick() override;

  NavigateOptions options_;
  Sightings sightings_;
  std::vector<std::pair<kurt_loop::Pose2, double>> stalled_;  // where, and the heading taken
};

}  // namespace kurt_navigate
