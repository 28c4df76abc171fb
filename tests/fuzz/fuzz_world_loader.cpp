// Fuzzes the world loader from bytes: a bundle of files held in memory (the root world, its
// imports and textures), so IMPORT chains, cycles, fan-outs and BMP decoding are all reached.
// A world that loads is built, checked for objects that start inside each other (the check
// macsim runs on every world it loads) and stepped; what must hold of any world is checked after
// each step. A WorldFileError is the expected answer to bad input; anything else escaping, an
// abort inside ODE, a sanitizer report or a broken invariant is a finding.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "fuzz_input.h"
#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "quiet_log.h"
#include "support/world_invariants.h"

// The loader's warnings for every input would drown the fuzzer's own output.
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace macsim;
  MemoryFiles files;
  for (auto& [name, bytes] : fuzz::split_bundle({reinterpret_cast<const char*>(data), size})) {
    files.add("fuzz/" + name, std::move(bytes));
  }
  LoadOptions options;
  options.files = &files;
  options.limits.max_objects = 2000;  // keeps one run fast; the limit itself is what is tested
  options.limits.max_imported_files = 200;
  WorldSpec spec;
  try {
    spec = load_world_file("fuzz/world.xml", options);
  } catch (const WorldFileError&) {
    return 0;  // refused with a file and a line: the answer bad input should get
  }
  World world(std::move(spec));  // a loaded world must build: anything thrown is a finding
  // Whatever the sizes and poses, the overlap check finishes with pairs it can report.
  const OverlapReport overlaps = world.overlaps();
  for (const auto& pair : overlaps.pairs) {
    if (!(pair.depth > kOverlapTolerance) || !std::isfinite(pair.depth) || pair.first.empty() ||
        pair.second.empty()) {
      std::fprintf(stderr, "overlap report broken: '%s' and '%s' at %g m\n", pair.first.c_str(),
                   pair.second.c_str(), pair.depth);
      std::abort();
    }
  }
  if (overlaps.pairs.size() > kMaxOverlapPairs || overlap_warnings(overlaps).size() > 21) {
    std::fprintf(stderr, "overlap report not capped: %zu pairs\n", overlaps.pairs.size());
    std::abort();
  }
  test::step_keeping_invariants(world, 10);
  return 0;
}
