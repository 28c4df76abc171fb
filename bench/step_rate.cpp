// Steps a world as fast as possible and prints `name value unit` lines.
#include <chrono>
#include <cstdio>
#include <string>

#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world_loader.h"

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help") {
    std::printf(
        "usage: bench_step_rate WORLD_FILE [SIM_SECONDS]\n"
        "Steps the world (robots driving in a circle) and prints steps/s.\n");
    return argc < 2 ? 2 : 0;
  }
  const double seconds = argc > 2 ? std::stod(argv[2]) : 10.0;
  macsim::Runner sim(macsim::load_world_file(argv[1]));
  auto& world = sim.world();
  const auto steps = static_cast<long>(seconds / world.step_size());
  const auto start = std::chrono::steady_clock::now();
  for (long i = 0; i < steps; ++i) {
    if (i % 100 == 0) {
      for (auto& robot : world.robots()) robot->command_twist(0.3, 0.2, world.time());
    }
    sim.step();
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string name = world.spec().name;
  std::printf("step_rate.%s %.0f steps/s\n", name.c_str(), steps / wall);
  std::printf("real_time_factor.%s %.1f x\n", name.c_str(), world.time() / wall);
  return 0;
}
