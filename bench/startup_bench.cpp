// What a process costs to start: programs of the build run with --help (they parse their
// command line and exit; no DDS), the CPU time of each start (user + system, from the reaped
// children's resource use) and its wall time, medians. Beside each, the baseline of the same
// run: the same start with the image codecs' module preloaded (LD_PRELOAD), which loads OpenCV's
// imgcodecs and the libraries it links as every program did when it linked imgcodecs itself.
//   bench_startup [STARTS]   (default 20 per program and set-up, taken in turn)
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "macsim/images/image_files.h"
#include "macsim/process/child_process.h"

namespace {

using Clock = std::chrono::steady_clock;
using macsim::process::ChildProcess;
using macsim::process::Output;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

double children_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

struct Start {
  double cpu = 0, wall = 0;
  bool ok = false;
};

/// One start of `program --help`, with `environment` on top of this process's.
Start start_once(const std::string& program, const std::vector<std::string>& environment) {
  macsim::process::Options options;
  options.output = Output::discard();
  options.environment = environment;
  const double cpu_before = children_cpu_seconds();
  const auto wall_before = Clock::now();
  ChildProcess p({program, "--help"}, options);
  const auto code = p.wait_for_exit(std::chrono::seconds(30));
  Start s;
  s.wall = std::chrono::duration<double>(Clock::now() - wall_before).count();
  s.cpu = children_cpu_seconds() - cpu_before;
  s.ok = code == 0;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string arg = argc > 1 ? argv[1] : "";
  if (arg == "--help" || arg == "-h") {
    std::printf("usage: bench_startup [STARTS]  (default 20 starts per program and set-up)\n");
    return 0;
  }
  int starts = 20;
  if (argc > 2 || (argc == 2 && (std::sscanf(argv[1], "%d", &starts) != 1 || starts <= 0 ||
                                 std::to_string(starts) != argv[1]))) {
    std::fprintf(stderr, "bench_startup: STARTS must be positive, not '%s'\n", argv[1]);
    return 2;
  }
  const std::string module = macsim::images::codecs_module_file();
  if (module.empty() || !std::filesystem::exists(module)) {
    std::fprintf(stderr, "bench_startup: no image codecs' module at %s\n", module.c_str());
    return 1;
  }
  int failed = 0;
  for (const char* name : {"macsim", "kurt_demo", "kurt_plan", "sim_core_tests"}) {
    const std::string program = macsim::process::sibling_program(name);
    if (!std::filesystem::exists(program)) continue;  // a build without the tests
    std::vector<double> cpu, wall, cpu_codecs, wall_codecs;
    for (int i = 0; i < starts; ++i) {  // in turn, so both see the same machine noise
      const Start bare = start_once(program, {});
      const Start with = start_once(program, {"LD_PRELOAD=" + module});
      if (!bare.ok || !with.ok) ++failed;
      cpu.push_back(bare.cpu);
      wall.push_back(bare.wall);
      cpu_codecs.push_back(with.cpu);
      wall_codecs.push_back(with.wall);
    }
    std::printf("startup.%s.cpu %.1f ms\n", name, 1e3 * median(cpu));
    std::printf("startup.%s.wall %.1f ms\n", name, 1e3 * median(wall));
    std::printf("startup.%s.cpu_codecs_loaded %.1f ms\n", name, 1e3 * median(cpu_codecs));
    std::printf("startup.%s.wall_codecs_loaded %.1f ms\n", name, 1e3 * median(wall_codecs));
    std::printf("startup.%s.cpu_ratio %.2f x\n", name,
                median(cpu) / std::max(1e-9, median(cpu_codecs)));
  }
  if (failed) std::fprintf(stderr, "bench_startup: %d starts did not exit 0\n", failed);
  return failed ? 1 : 0;
}
