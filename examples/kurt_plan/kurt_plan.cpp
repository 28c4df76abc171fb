// kurt_plan: reaches a goal nobody scripted. It perceives the room with the KURT3D's own sensors,
// plans over a domain of what its behaviours do (learned from trials, --affordances DIR, or written
// by hand, --pddl-domain FILE), executes the plan with the behaviours, watches each step's effect
// and plans again when it differs from the prediction; what stands in its way it judges by the
// traverse model in DIR, when there is one. Against macsim or the real robot.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"
#include "macsim/affordances/traverse.h"
#include "plan_controller.h"

int main(int argc, char** argv) {
  // No default domain: a program that moves a robot acts only where it is told to.
  macsim::dds::ParticipantOptions participant{-1, "", "kurt_plan"};
  kurt_plan::PlanOptions options;
  std::string goal = "through-door", affordances, pddl_domain;
  macsim::dds::CommandLine cli(
      "kurt_plan",
      "Reaches a goal by planning over what the KURT3D's behaviours do, from its own sensors: "
      "perceives the room, plans, acts, watches each step and plans again when a step's effect "
      "differs from the prediction.\nExit 0: the goal reached; 1: an internal error; 2: usage; "
      "3: no robot; 4: no plan reaches the goal from what the robot perceives; 5: the steps or "
      "replans ran out; 7: timeout.\n--domain N is required (it moves a robot: never on a domain "
      "it was not given).");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.option("goal", "GOAL",
             "through-door (the robot beyond the door; the default), switch-pressed, or "
             "on-switch:COLOUR (a thing of that colour on the switch's platform)",
             &goal);
  cli.option("affordances", "DIR",
             "what the robot learned: plan over DIR/effects.ppddl (learn_effects --out DIR), and "
             "judge what stands in the way by DIR/traverse.yml when it is there (affordance_learn "
             "--features shape --save-model DIR)",
             &affordances);
  cli.option("pddl-domain", "FILE",
             "plan over this PDDL domain instead of DIR/effects.ppddl (e.g. the hand-written "
             "affordances/domains/kurt3d_room_by_hand.pddl)",
             &pddl_domain);
  cli.option("problems", "DIR", "write each planning round's problem (the perceived scene) here",
             &options.problems);
  cli.option("debug-images", "DIR", "write each camera image looked at, with what was seen",
             &options.debug_images);
  cli.flag("pictures",
           "after each step, ask the simulator (macsim --pictures DIR) for an overview picture and "
           "write it with the plan drawn beside it as NAME_plan.png",
           &options.pictures);
  // Pushing a box takes legs of slow driving: more robot time than a lift and carry.
  options.loop.timeout = 900.0;
  std::string policy = "plan";
  cli.option("policy", "POLICY",
             "plan (the default), or random: each step chosen at random among those the domain "
             "allows in the perceived scene, with the same step budget (a baseline)",
             &policy);
  int policy_seed = 1;
  cli.option("policy-seed", "N", "the random policy's seed (default 1)", &policy_seed);
  macsim::affordances::add_loop_options(cli, options.loop);
  if (auto code = cli.parse(argc, argv)) return *code;
  const auto parsed = kurt_plan::Goal::parse(goal);
  if (!parsed) {
    macsim::log::error("kurt_plan: --goal is through-door, switch-pressed or on-switch:COLOUR, not '{}'",
                       goal);
    return kurt_plan::kUsage;
  }
  options.goal = *parsed;
  if (policy != "plan" && policy != "random") {
    macsim::log::error("kurt_plan: --policy is plan or random, not '{}'", policy);
    return kurt_plan::kUsage;
  }
  options.policy = policy == "random" ? kurt_plan::Policy::Random : kurt_plan::Policy::Plan;
  if (policy_seed < 0) {
    macsim::log::error("kurt_plan: --policy-seed is a number from 0, not {}", policy_seed);
    return kurt_plan::kUsage;
  }
  options.policy_seed = static_cast<std::uint32_t>(policy_seed);
  if (affordances.empty() && pddl_domain.empty()) {
    macsim::log::error("kurt_plan: give --affordances DIR, --pddl-domain FILE, or both");
    return kurt_plan::kUsage;
  }
  if (const auto problem = macsim::affordances::loop_options_problem(options.loop); !problem.empty()) {
    macsim::log::error("kurt_plan: {}", problem);
    return kurt_plan::kUsage;
  }
  if (const auto problem = macsim::affordances::debug_images_problem(options.debug_images); !problem.empty()) {
    macsim::log::error("kurt_plan: {}", problem);
    return kurt_plan::kUsage;
  }
  if (!options.problems.empty() && !std::filesystem::is_directory(options.problems)) {
    macsim::log::error("kurt_plan: --problems {} is no folder", options.problems);
    return kurt_plan::kUsage;
  }
  try {
    options.domain = macsim::affordances::pddl::load_domain(
        pddl_domain.empty() ? affordances + "/effects.ppddl" : pddl_domain);
    if (pddl_domain.empty() && std::filesystem::exists(affordances + "/thresholds.yml"))
      options.thresholds = macsim::affordances::load_thresholds(affordances + "/thresholds.yml");
  } catch (const macsim::affordances::pddl::PddlError& e) {
    macsim::log::error("kurt_plan: {}", e.what());
    return kurt_plan::kUsage;
  }
  try {
    if (!affordances.empty() && std::filesystem::exists(affordances + "/traverse.yml"))
      options.traverse_model = macsim::affordances::load_traverse_model(affordances);
  } catch (const std::exception& e) {
    macsim::log::error("kurt_plan: --affordances: {}", e.what());
    return kurt_plan::kUsage;
  }
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    macsim::dds::Participant dds(participant);
    kurt_plan::PlanController controller(dds, options);
    kurt_plan::Summary summary;
    try {
      summary = controller.run();
    } catch (const macsim::affordances::LoopError& e) {
      constexpr kurt_plan::Exit kCodes[] = {kurt_plan::kNoRobot, kurt_plan::kTimeout,
                                            kurt_plan::kNotReached};
      summary = controller.summary();
      summary.exit = kCodes[static_cast<int>(e.stop)];
      summary.reason = e.what();
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (!summary.reached) std::printf("kurt_plan: the goal %s was not reached: %s\n", parsed->text().c_str(), summary.reason.c_str());
    char line[256];
    std::snprintf(line, sizeof line,
                  "goal reached: %s, plan steps: %d, replans: %d, robot time: %.1f s, planning time: %.1f ms, "
                  "wall time: %.1f s",
                  summary.reached ? "yes" : "no", summary.plan_steps, summary.replans, controller.elapsed(),
                  1e3 * summary.planning_seconds, wall);
    std::printf("kurt_plan: %s\n", line);
    controller.publish_outcome(line);
    return summary.exit;
  } catch (const macsim::dds::DdsError& e) {
    macsim::log::error("kurt_plan: DDS error: {}", e.what());
    return kurt_plan::kNoRobot;
  } catch (const std::exception& e) {
    macsim::log::error("kurt_plan: {}", e.what());
    return 1;
  }
}
