// kurt_navigate: drives the KURT3D to a goal through clutter by learned traversability: it
// scans with its rotating laser, stands before each thing in its way as a traverse trial stood,
// computes the trials' features there and asks the traverse model, and drives the cheapest way
// to the goal over the floor and what the model calls traversable. --policy avoid is the
// baseline: every return above the floor is an obstacle.
// Against macsim or the real KURT3D (it decides from the robot's own topics only).
#include <chrono>
#include <cmath>
#include <cstdio>

#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"
#include "navigator.h"

int main(int argc, char** argv) {
  using namespace kurt_navigate;
  // No default domain: a program that moves a robot acts only where it is told to.
  macsim::dds::ParticipantOptions participant{-1, "", "kurt_navigate"};
  NavigateOptions options;
  options.loop.timeout = 300;
  macsim::dds::CommandLine cli(
      "kurt_navigate",
      "Drives a KURT3D to a goal through clutter from its 3D laser, by a learned traverse model "
      "(into what rolls away, over what is low, around the rest) or by avoiding everything.\n"
      "Exit 0: at the goal; 1: an internal error; 2: usage; 3: no robot; 4: no way judged "
      "passable; 7: timeout; 9: no laser cloud.\n--domain N is required (it moves a robot: "
      "never on a domain it was not given).");
  cli.participant_options(&participant, /*domain_required=*/true);
  macsim::affordances::add_loop_options(cli, options.loop);
  std::string goal = "6,0", policy = "model", affordances;
  cli.option("goal", "X,Y", "the goal in the odometry frame, m (default 6,0: 6 m ahead)", &goal);
  cli.option("policy", "model|avoid",
             "judge what stands in the way by the traverse model (default) or avoid every "
             "return above the "
             "floor (the baseline)",
             &policy);
  cli.option("affordances", "DIR",
             "the traverse model DIR/traverse.yml (affordance_learn --features shape "
             "--save-model DIR); required by --policy model",
             &affordances);
  cli.flag("verbose",
           "also print, at each look, the laser odometry's fit and every thing seen with its "
           "judgement",
           &options.verbose);
  cli.option("tolerance", "METRES", "how near the goal counts as there (default 0.3)",
             &options.tolerance);
  if (auto code = cli.parse(argc, argv)) return *code;
  char comma = 0, rest = 0;
  if (std::sscanf(goal.c_str(), "%lf%c%lf%c", &options.goal_x, &comma, &options.goal_y, &rest) !=
          3 ||
      comma != ',' || !std::isfinite(options.goal_x) || !std::isfinite(options.goal_y) ||
      std::fabs(options.goal_x) > 1e4 || std::fabs(options.goal_y) > 1e4) {
    macsim::log::error("kurt_navigate: --goal takes X,Y in metres (finite, within 10 km), not '{}'",
                       goal);
    return kUsage;
  }
  if (const auto problem = macsim::affordances::loop_options_problem(options.loop); !problem.empty()) {
    macsim::log::error("kurt_navigate: {}", problem);
    return kUsage;
  }
  if (!(options.tolerance > 0)) {
    macsim::log::error("kurt_navigate: --tolerance must be positive");
    return kUsage;
  }
  if (policy == "avoid") {
    options.policy = Policy::Avoid;
  } else if (policy != "model") {
    macsim::log::error("kurt_navigate: --policy is model or avoid, not '{}'", policy);
    return kUsage;
  } else if (affordances.empty()) {
    macsim::log::error(
        "kurt_navigate: --policy model needs --affordances DIR (a traverse model: "
        "affordance_learn --features shape --save-model DIR), or use --policy avoid");
    return kUsage;
  }
  if (options.policy == Policy::Model) {
    try {
      options.traverse_model = macsim::affordances::load_traverse_model(affordances);
    } catch (const std::exception& e) {
      macsim::log::error("kurt_navigate: --affordances: {}", e.what());
      return kUsage;
    }
  }
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  try {
    macsim::dds::Participant dds(participant);
    Navigator navigator(dds, options);
    const Outcome out = navigator.run();
    const char* verdict = out.code == kAtGoal ? "AT GOAL" : "FAILED";
    std::printf(
        "kurt_navigate: %s%s%s (policy %s): robot time %.1f s, wall time %.1f s, stretches %d, "
        "stalls %d; things seen %d: driven through %d, driven around %d\n",
        verdict, out.reason.empty() ? "" : ": ", out.reason.c_str(), policy.c_str(),
        navigator.elapsed(), wall(), out.stretches, out.stalls, out.things.seen, out.things.through,
        out.things.around);
    return out.code;
  } catch (const macsim::dds::DdsError& e) {
    macsim::log::error("kurt_navigate: DDS error: {}", e.what());
    return kNoRobot;
  } catch (const std::exception& e) {
    macsim::log::error("kurt_navigate: {}", e.what());
    return 1;
  }
}
