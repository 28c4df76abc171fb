// kurt_demo: the MACS final demonstrator, played by the robot's own sensing over DDS. Scene 1:
// finds cans with its stereo cameras; scene 2: lifts one with the crane's magnet (trying the
// next when one does not come up); scene 3: drops it on the door's floor switch; scene 4: sees
// the door open with its 3D laser and drives through. Against macsim or the real KURT3D. With
// --affordances DIR it ranks the cans by a learned lift model before trying any.
#include <chrono>
#include <cstdio>
#include <iostream>

#include "demo_controller.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"

int main(int argc, char** argv) {
  // No default domain: a program that moves a robot acts only where it is told to.
  macsim::dds::ParticipantOptions participant{-1, "", "kurt_demo"};
  kurt_demo::DemoOptions options;
  macsim::dds::CommandLine cli(
      "kurt_demo",
      "Plays the MACS final demonstrator with a KURT3D from its own sensors: finds a can, lifts "
      "it with the crane's magnet, drops it on the door's switch, drives through the opened "
      "door.\nExit 0: through the door; 1: an internal error; 2: usage; 3: no robot; 4: no can found; 5: no can could "
      "be lifted; 6: the door stayed closed; 7: timeout; 8: no switch found; 9: could not get "
      "through.\n--domain N is required (it moves a robot: never on a domain it was not given).");
  cli.participant_options(&participant, /*domain_required=*/true);
  macsim::affordances::add_loop_options(cli, options.loop);
  cli.flag("pictures",
           "ask the simulator (macsim --pictures DIR) for an overview picture per scene",
           &options.pictures);
  cli.option("debug-images", "DIR", "write each camera image looked at, with what was seen",
             &options.debug_images);
  std::string affordances;
  cli.option("affordances", "DIR",
             "rank the cans by the lift model DIR/lift.yml (affordance_learn --save-model, on "
             "features the cameras give from where the robot stands) before trying any",
             &affordances);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (const auto problem = macsim::affordances::loop_options_problem(options.loop); !problem.empty()) {
    macsim::log::error("kurt_demo: {}", problem);
    return kurt_demo::kUsage;
  }
  if (const auto problem = macsim::affordances::debug_images_problem(options.debug_images); !problem.empty()) {
    macsim::log::error("kurt_demo: {}", problem);
    return kurt_demo::kUsage;
  }
  if (!affordances.empty()) {
    try {
      options.lift_model = kurt_demo::load_lift_model(affordances);
    } catch (const kurt_demo::Failure& failure) {
      macsim::log::error("kurt_demo: --affordances: {}", failure.reason);
      return kurt_demo::kUsage;
    }
  }
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  try {
    macsim::dds::Participant dds(participant);
    kurt_demo::DemoController demo(dds, options);
    auto failed = [&](int code, const std::string& reason) {
      std::printf(
          "kurt_demo: FAILED (exit %d): %s; robot time %.1f s, wall time %.1f s, lift "
          "attempts: %d\n",
          code, reason.c_str(), demo.elapsed(), wall(), demo.lift_attempts());
      return code;
    };
    try {
      demo.run();
    } catch (const kurt_demo::Failure& failure) {
      return failed(failure.code, failure.reason);
    } catch (const macsim::affordances::LoopError& e) {
      constexpr kurt_demo::Exit kCodes[] = {kurt_demo::kNoRobot, kurt_demo::kTimeout,
                                            kurt_demo::kNoPassage};
      return failed(kCodes[static_cast<int>(e.stop)], e.what());
    }
    std::printf(
        "kurt_demo: SUCCESS: the robot is through the door; robot time %.1f s, wall time "
        "%.1f s, lift attempts: %d\n",
        demo.elapsed(), wall(), demo.lift_attempts());
  } catch (const macsim::dds::DdsError& e) {
    macsim::log::error("kurt_demo: DDS error: {}", e.what());
    return kurt_demo::kNoRobot;
  } catch (const std::exception& e) {
    macsim::log::error("kurt_demo: {}", e.what());
    return 1;
  }
  return 0;
}
