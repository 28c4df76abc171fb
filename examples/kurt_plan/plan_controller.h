// kurt_plan's controller: perceives the room with the behaviours' sensing, makes the scene a PDDL
// problem, plans over a domain (learned, or written by hand), executes the plan with the
// behaviours, compares each step's perceived effect with the predicted one, and plans again from
// what it sees when they differ. It reads the robot's own topics only.
#pragma once

#include <memory>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "macsim/affordances/behaviours.h"
#include "macsim/affordances/effects.h"
#include "macsim/affordances/pddl.h"
#include "macsim/affordances/planner.h"
#include "macsim/affordances/scene_atoms.h"
#include "macsim/dds/participant.h"
#include "macsim/msg/plan_msgsPubSubTypes.h"

namespace kurt_plan {

/// Exit codes.
enum Exit : int {
  kReached = 0,
  kUsage = 2,
  kNoRobot = 3,
  kUnreachable = 4,  ///< no plan reaches the goal from what the robot perceives
  kNotReached = 5,   ///< the plans' steps ran out (replans or steps over their budget)
  kTimeout = 7,
};

/// A goal as the robot can perceive it: `through-door`, `switch-pressed`, `on-switch:COLOUR`.
struct Goal {
  enum class Kind { ThroughDoor, SwitchPressed, OnSwitch } kind = Kind::ThroughDoor;
  std::string colour;  ///< of OnSwitch
  /// Parses the command line's form; nullopt for anything else.
  static std::optional<Goal> parse(const std::string& text);
  std::string text() const;
};

/// How the next step is chosen: by planning to the goal, or at random among the steps the
/// domain allows in the perceived scene (the baseline, with the same step budget).
enum class Policy { Plan, Random };

struct PlanOptions {
  macsim::affordances::LoopOptions loop;
  Goal goal;
  macsim::affordances::pddl::Domain domain;  ///< what the planner plans over
  /// A learned domain's thresholds: the atoms each thing's perceived features make true.
  std::vector<macsim::affordances::Threshold> thresholds;
  /// A traverse model, asked about what stands in the way when no way round it is free.
  std::optional<macsim::affordances::AffordanceModel> traverse_model;
  std::string problems;  ///< a folder to write each planning round's problem file to, or empty
  std::string debug_images;  ///< a folder for the camera images looked at, with what was seen
  bool pictures = false;     ///< ask the simulator for an overview picture after each step, and draw the plan on it
  int max_replans = 8;
  int max_steps = 40;
  Policy policy = Policy::Plan;
  std::uint32_t policy_seed = 1;  ///< of Policy::Random's choices
};

/// How the run ended.
struct Summary {
  bool reached = false;
  int plan_steps = 0;  ///< steps executed
  int replans = 0;
  double planning_seconds = 0;  ///< wall time of every planning round together
  Exit exit = kReached;
  std::string reason;
};

class PlanController : public macsim::affordances::Behaviours {
 public:
  PlanController(macsim::dds::Participant& participant, const PlanOptions& options);
  /// Perceives, plans, acts, watches and plans again until the goal holds or cannot be reached;
  /// throws macsim::affordances::LoopError (no robot, timeout, no cloud).
  Summary run();
  /// The run so far (after a LoopError too).
  const Summary& summary() const { return summary_; }
  /// Publishes the run's summary line as the plan's outcome (rt/<robot>/plan).
  void publish_outcome(const std::string& line);

  /// The perceived scene as a problem of the domain with this goal atom (objects: start, the
  /// things seen, nearest first, the switch, the door).
  macsim::affordances::pddl::Problem problem(const macsim::affordances::pddl::Atom& goal) const;

 private:
  /// The goal atoms the goal may be met by (one per thing of the colour for on-switch).
  std::vector<macsim::affordances::pddl::Atom> goal_atoms() const;
  /// True when the perceived scene shows the goal.
  bool goal_holds() const;
  /// Policy::Plan's run after the first look: plan, act, watch, plan again until the goal holds,
  /// no plan reaches it, or the steps or replans run out.
  void run_plan();
  /// Policy::Random's run after the first look: a step chosen at random among those the domain
  /// allows, executed and watched, until the goal holds or the step budget is spent.
  void run_random();
  /// Step `i` of the plan shown: under way, executed through its behaviour, its outcome shown
  /// and pictured; after a thing was not where it was seen, a look around. True as predicted.
  bool act(std::size_t i, const macsim::affordances::PlanStep& step);
  /// True (and the summary says so) once the step budget is spent.
  bool out_of_steps();
  /// A step as the plan topic shows it, still to do.
  static plan_msgs::msg::dds_::PlanStep_ shown_step(const macsim::affordances::PlanStep& step);
  /// Plans for each goal atom and keeps the shortest, likeliest; nullopt and the reason if none.
  std::optional<macsim::affordances::Plan> plan_round(std::string& reason, double& seconds);
  /// Runs one step through its behaviour; true when what it perceived afterwards shows the
  /// step's predicted effect; `outcome` says so, or what it perceived instead.
  bool execute(const macsim::affordances::PlanStep& step, std::string& outcome);
  /// The plan on rt/<robot>/plan: the steps as they stand, the things as judged now.
  void publish_plan();
  /// Each thing not lost with what the controller judges of it: on the switch, lifted, did not
  /// come up, or liftable / not liftable with the probability that a plan to hold it succeeds.
  std::vector<plan_msgs::msg::dds_::JudgedThing_> judged_things() const;

  /// An overview picture (Behaviours::overview_picture()) and beside it `<name>_plan.png` with the
  /// plan drawn on its right.
  void picture(const std::string& name);

  PlanOptions options_;
  macsim::dds::Writer<plan_msgs::msg::dds_::Plan_PubSubType> plan_writer_;
  plan_msgs::msg::dds_::Plan_ shown_;  ///< what was published last
  Summary summary_;
  int round_ = 0;
};

}  // namespace kurt_plan
