// The world-file argument of the sim_core benchmarks: `--help` (or `-h`) prints the usage, an
// unknown option or a world that cannot be loaded is a clear error, never an abort.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

#include "macsim/sim_core/world_loader.h"

namespace macsim::bench {

/// The world named by argv[1] (or `fallback`); nullopt with `exit_code` set when the program
/// should exit now (0 after --help, 2 on a bad argument, 1 on a world that cannot be loaded).
inline std::optional<WorldSpec> world_argument(int argc, char** argv, const char* usage,
                                               const std::string& fallback, int& exit_code) {
  const std::string arg = argc > 1 ? argv[1] : fallback;
  if (arg == "--help" || arg == "-h") {
    std::printf("%s\n", usage);
    exit_code = 0;
    return std::nullopt;
  }
  if (arg.empty() || arg[0] == '-') {
    std::fprintf(stderr, "%s: unknown option '%s'\n%s\n", argv[0], arg.c_str(), usage);
    exit_code = 2;
    return std::nullopt;
  }
  try {
    return load_world_file(arg);
  } catch (const WorldFileError& e) {
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    exit_code = 1;
    return std::nullopt;
  }
}

}  // namespace macsim::bench
