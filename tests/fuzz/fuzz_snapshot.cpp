// Fuzzes World::restore() with snapshot bytes: what a client, a session or a damaged file may
// hand it. Each run starts from the scene's first snapshot (tests/fuzz/snapshot_scene.h: two
// robot types, a can held by the magnet, a pile asleep). A refused snapshot must change
// nothing; an accepted one must come back bit for bit (the state's bytes are the snapshot's)
// and step; what must hold of any world is checked after each step. Anything thrown, an abort
// inside ODE or a sanitizer report is a finding.
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "finding.h"
#include "macsim/sim_core/log_sink.h"
#include "quiet_log.h"
#include "snapshot_scene.h"
#include "support/world_invariants.h"

namespace {

struct Fixture {
  std::unique_ptr<macsim::World> world = macsim::fuzz::snapshot_scene();
  macsim::WorldSnapshot initial = world->snapshot();
  uint64_t initial_hash = world->state_hash();
};

using macsim::fuzz::finding;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace macsim;
  static Fixture fixture;
  World& world = *fixture.world;
  if (!world.restore(fixture.initial).ok()) finding("the initial snapshot is refused");
  const std::vector<uint8_t> bytes(data, data + size);
  if (!world.restore({world.fingerprint(), bytes}).ok()) {
    if (world.state_hash() != fixture.initial_hash) finding("a refused snapshot changed the world");
    return 0;
  }
  if (serialize(world.state()) != bytes) finding("a restored state differs from its snapshot");
  test::step_keeping_invariants(world, 10);
  return 0;
}
