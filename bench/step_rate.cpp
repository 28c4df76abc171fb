// Steps a world as fast as possible and prints `name value unit` lines.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_world_arg.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world_loader.h"

int main(int argc, char** argv) {
  const char* usage =
      "usage: bench_step_rate WORLD_FILE [SIM_SECONDS]\n"
      "Steps the world (robots driving in a circle) and prints steps/s.";
  if (argc < 2) {
    std::fprintf(stderr, "%s\n", usage);
    return 2;
  }
  int exit_code = 0;
  auto loaded = macsim::bench::world_argument(argc, argv, usage, "", exit_code);
  if (!loaded) return exit_code;
  char* end = nullptr;
  const double seconds = argc > 2 ? std::strtod(argv[2], &end) : 10.0;
  if (argc > 2 && (*end != '\0' || !(seconds > 0) || seconds > 1e6)) {
    std::fprintf(stderr, "bench_step_rate: SIM_SECONDS must be a number in (0, 1e6], got '%s'\n",
                 argv[2]);
    return 2;
  }
  macsim::Runner sim(std::move(*loaded));
  auto& world = sim.world();
  const auto steps = static_cast<long>(seconds / world.step_size());
  const auto start = std::chrono::steady_clock::now();
  for (long i = 0; i < steps; ++i) {
    if (i % 100 == 0) {
      for (auto& robot : world.robots())
        robot->execute(macsim::robot::Twist{0.3, 0.2}, world.time());
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
