// The simulation loop's core: queued commands apply at the step, and runs are deterministic.
#include "macsim/sim_core/simulation.h"

#include <gtest/gtest.h>

#include <thread>

#include "macsim/sim_core/world_loader.h"
#include "support/child_process.h"

namespace macsim {
namespace {

TEST(CommandQueue, CommandsRunOnlyWhenTheSimulationSteps) {
  Simulation sim(load_world_file(test::source("worlds/small_room.xml")));
  int applied = 0;
  std::thread producer([&] {
    for (int i = 0; i < 100; ++i) sim.commands().push([&applied](World&) { ++applied; });
  });
  producer.join();
  EXPECT_EQ(applied, 0);  // nothing touched the world from the producer's thread
  sim.step();
  EXPECT_EQ(applied, 100);
  sim.step();
  EXPECT_EQ(applied, 100);
}

TEST(CommandQueue, CommandsRunInArrivalOrderBeforeTheStep) {
  Simulation sim(load_world_file(test::source("worlds/small_room.xml")));
  std::vector<uint64_t> seen_at_step;
  sim.commands().push([&](World& w) { seen_at_step.push_back(w.steps()); });
  sim.commands().push([&](World& w) { seen_at_step.push_back(w.steps() + 100); });
  sim.step();
  ASSERT_EQ(seen_at_step.size(), 2u);
  EXPECT_EQ(seen_at_step[0], 0u);    // ran before the step advanced time
  EXPECT_EQ(seen_at_step[1], 100u);
  EXPECT_EQ(sim.world().steps(), 1u);
}

TEST(Simulation, SameWorldAndCommandsGiveBitIdenticalStates) {
  auto run = [] {
    Simulation sim(load_world_file(test::source("worlds/small_room.xml")));
    for (int i = 0; i < 2000; ++i) {
      if (i % 100 == 0) {
        sim.commands().push([](World& w) { w.robot("kurt")->command_twist(0.3, 0.4, w.time()); });
      }
      sim.step();
    }
    std::vector<double> state;
    const Pose p = sim.world().robot("kurt")->base_footprint_pose();
    state.insert(state.end(), p.position.data(), p.position.data() + 3);
    state.insert(state.end(), p.orientation.coeffs().data(), p.orientation.coeffs().data() + 4);
    for (ObjectId id : sim.world().object_ids()) {
      const Pose o = sim.world().object_state(id).value.pose;
      state.insert(state.end(), o.position.data(), o.position.data() + 3);
    }
    return state;
  };
  const auto first = run();
  const auto second = run();
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) EXPECT_EQ(first[i], second[i]) << "index " << i;
}

}  // namespace
}  // namespace macsim
