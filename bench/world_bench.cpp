// sim_core step rate against raw ODE on the same bodies and geoms, step rate for 10 / 100 /
// 1000 portable objects, grids of resting boxes and ODE's own floor under them, tangled starts
// against the same things apart, the overlap check's cost, and the cost of snapshot, restore and
// reset.
// Prints `name value unit`.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "bench_world_arg.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "macsim/sim_core/world_overlaps.h"
#include "raw_ode_world.h"
#include "scenes.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Steps per second over `seconds` of sim time, after a 0.5 s warm-up.
double rate(const std::function<void()>& step, double dt, double seconds) {
  for (int i = 0; i < static_cast<int>(0.5 / dt); ++i) step();
  const long steps = static_cast<long>(seconds / dt);
  const auto start = Clock::now();
  for (long i = 0; i < steps; ++i) step();
  return steps / seconds_since(start);
}

}  // namespace

int main(int argc, char** argv) {
  int exit_code = 0;
  const auto loaded = macsim::bench::world_argument(
      argc, argv,
      "usage: bench_world [WORLD_FILE]  (default worlds/DemoWorld_v1.xml, from the repo root)",
      "worlds/DemoWorld_v1.xml", exit_code);
  if (!loaded) return exit_code;
  const macsim::WorldSpec& spec = *loaded;

  // 1. sim_core against raw ODE, alternating runs so both see the same machine noise.
  std::vector<double> core_rates, raw_rates;
  for (int repeat = 0; repeat < 5; ++repeat) {
    macsim::World world(spec);
    core_rates.push_back(rate(
        [&] {
          if (world.steps() % 100 == 0) {
            for (auto& r : world.robots()) r->execute(macsim::robot::Twist{0.3, 0.0}, world.time());
          }
          world.step();
        },
        world.step_size(), 2.0));
    macsim::bench::RawOdeWorld raw(spec);
    raw.drive(0.3);
    raw_rates.push_back(rate([&] { raw.step(); }, 0.001, 2.0));
  }
  const double core = median(core_rates), raw = median(raw_rates);
  std::printf("step_rate.%s.sim_core %.0f steps/s\n", spec.name.c_str(), core);
  std::printf("step_rate.%s.raw_ode %.0f steps/s\n", spec.name.c_str(), raw);
  std::printf("cost_ratio.%s.sim_core_over_raw_ode %.3f x\n", spec.name.c_str(), raw / core);

  // 2. Many portable objects.
  for (int n : {10, 100, 1000}) {
    macsim::World world(macsim::bench::pile(n));
    const double seconds = n >= 1000 ? 0.5 : 2.0;
    std::printf("step_rate.objects_%d %.0f steps/s\n", n,
                rate([&] { world.step(); }, world.step_size(), seconds));
  }

  // 2b. Scale: grids of boxes resting on the floor (asleep once settled); the cost should grow
  // about linearly with their number.
  std::map<int, double> resting, overlap_check;
  auto check_time = [](const macsim::World& world) {  // World::overlaps(), median of 5
    std::vector<double> times;
    for (int i = 0; i < 5; ++i) {
      const auto start = Clock::now();
      const auto report = world.overlaps();
      times.push_back(seconds_since(start));
      if (report.truncated) std::printf("#\n");  // keep the report
    }
    return median(times);
  };
  std::map<int, double> first_half_second, ode_floor;
  for (int n : {1000, 5000, 20000}) {
    macsim::World world(macsim::bench::resting_boxes(n));
    // 2c. The overlap check macsim runs on a world it loads: each box touches the floor.
    overlap_check[n] = check_time(world);
    std::printf("overlaps.resting_boxes_%d %.2f ms\n", n, overlap_check[n] * 1e3);
    // Awake: their first half second, before they fall asleep (50 steps still).
    const int half_second = static_cast<int>(0.5 / world.step_size());
    auto start = Clock::now();
    for (int i = 0; i < half_second; ++i) world.step();
    first_half_second[n] = half_second / seconds_since(start);
    std::printf("step_rate.resting_boxes_%d.first_half_second %.1f steps/s\n", n,
                first_half_second[n]);
    start = Clock::now();
    int steps = 0;
    while (seconds_since(start) < 1.0 || steps < 5) {
      world.step();
      ++steps;
    }
    resting[n] = steps / seconds_since(start);
    std::printf("step_rate.resting_boxes_%d %.1f steps/s\n", n, resting[n]);
    // The floor under it: ODE stepping the same number of sleeping bodies, nothing else.
    ode_floor[n] = macsim::bench::sleeping_bodies_rate(n, world.step_size());
    std::printf("step_rate.ode_sleeping_bodies_%d %.1f steps/s\n", n, ode_floor[n]);
  }
  // The world asleep against ODE's bare world of the same bodies asleep, per step (goal: 1.10).
  std::printf("asleep_20000.sim_core_over_ode %.3f\n", ode_floor[20000] / resting[20000]);
  std::printf("scale.resting_boxes_20000_over_5000 %.3f x (linear: 0.25)\n",
              resting[20000] / resting[5000]);
  std::printf("scale.resting_boxes_20000_over_5000.first_half_second %.3f x (linear: 0.25)\n",
              first_half_second[20000] / first_half_second[5000]);
  std::printf("scale.ode_sleeping_bodies_20000_over_5000 %.3f x (linear: 0.25)\n",
              ode_floor[20000] / ode_floor[5000]);
  std::printf(
      "share.resting_boxes_20000.ode_floor %.2f (of the step: ODE's own walk over its bodies)\n",
      resting[20000] / ode_floor[20000]);
  std::printf("scale.overlaps_20000_over_5000 %.2f x (linear: 4)\n",
              overlap_check[20000] / overlap_check[5000]);
  {  // the degenerate case: 200 boxes at one point, 19,900 pairs (examined up to the cap)
    macsim::WorldSpec point = macsim::bench::resting_boxes(200);
    for (auto& box : point.objects) box.pose.position = {0, 0, 0.05};
    const macsim::World world(point);
    std::printf("overlaps.boxes_at_one_point_200 %.2f ms\n", check_time(world) * 1e3);
  }

  // 2d. Tangled starts: 200 boxes at one point and 20 KURT3Ds at one point, loaded as macsim
  // loads them (parted on the floor, warned) and kept where they are (the physics alone),
  // against the same things placed apart; steps/s over their first second from construction.
  auto first_second = [](const macsim::WorldSpec& scene, double seconds) {
    macsim::World world(scene);
    const long steps = std::max(5L, static_cast<long>(seconds / world.step_size()));
    const auto began = Clock::now();
    for (long i = 0; i < steps; ++i) world.step();
    return steps / seconds_since(began);
  };
  // `heap` is `apart` with everything moved to one point; `name` says what it holds.
  auto tangled = [&](const std::string& name, const macsim::WorldSpec& apart,
                     const macsim::WorldSpec& heap) {
    macsim::WorldSpec parted = heap;
    const auto began = Clock::now();
    macsim::part_overlaps(parted);
    std::printf("part_overlaps.%s_at_one_point %.1f ms\n", name.c_str(),
                seconds_since(began) * 1e3);
    const double a = first_second(apart, 1.0), p = first_second(parted, 1.0);
    std::printf("step_rate.%s_apart.first_second %.0f steps/s\n", name.c_str(), a);
    std::printf("step_rate.%s_at_one_point.parted.first_second %.0f steps/s\n", name.c_str(), p);
    std::printf("step_rate.%s_at_one_point.kept.first_50_steps %.1f steps/s\n", name.c_str(),
                first_second(heap, 0.05));
    std::printf("tangled.%s_at_one_point_over_apart %.2f x (goal >= 0.1)\n", name.c_str(), p / a);
  };
  {
    const macsim::WorldSpec apart = macsim::bench::resting_boxes(200);
    macsim::WorldSpec heap = apart;
    for (auto& box : heap.objects) box.pose.position = {0, 0, 0.05};
    tangled("boxes_200", apart, heap);
  }
  {
    macsim::WorldSpec apart = macsim::bench::empty_world("kurts_apart_20");
    for (int i = 0; i < 20; ++i) {
      macsim::RobotSpec robot;
      robot.name = "kurt_" + std::to_string(i);
      robot.type = "kurt3d";
      robot.pose.position = {(i % 5) * 1.0, (i / 5) * 1.0, 0.0};
      apart.robots.push_back(robot);
    }
    macsim::WorldSpec heap = apart;
    for (auto& robot : heap.robots) robot.pose.position = {0, 0, 0};
    tangled("kurts_20", apart, heap);
  }

  // 3. Trials: snapshot, restore, reset, of a world 3 s in, its robots' lasers turning (their
  // clouds full: the largest part of the state); each measurement starts from that state.
  macsim::World world(spec);
  for (const auto& robot : world.robots())  // the laser turning, as controllers run it
    robot->execute(macsim::robot::RotunitSpeed{1.0}, world.time());
  for (int i = 0; i < static_cast<int>(3.0 / world.step_size()); ++i) world.step();
  const macsim::WorldSnapshot stepped = world.snapshot();
  std::vector<double> snap, restore, reset, state, hash;
  for (int i = 0; i < 20; ++i) {
    auto t = Clock::now();
    const macsim::WorldState parts = world.state();
    state.push_back(seconds_since(t));
    t = Clock::now();
    const uint64_t h = world.state_hash();
    hash.push_back(seconds_since(t));
    if (h == 0 && parts.steps == 0) std::printf("#\n");  // keep both
    t = Clock::now();
    const macsim::WorldSnapshot s = world.snapshot();
    snap.push_back(seconds_since(t));
    t = Clock::now();
    world.restore(stepped);
    restore.push_back(seconds_since(t));
  }
  for (int i = 0; i < 20; ++i) {
    auto t = Clock::now();
    world.reset(macsim::ResetScope::Everything);
    reset.push_back(seconds_since(t));
    world.restore(stepped);
  }
  std::printf("state_bytes.%s %zu B\n", spec.name.c_str(), stepped.bytes.size());
  std::printf("state.%s %.1f us\n", spec.name.c_str(), median(state) * 1e6);
  std::printf("state_hash.%s %.1f us\n", spec.name.c_str(), median(hash) * 1e6);
  std::printf("snapshot.%s %.1f us\n", spec.name.c_str(), median(snap) * 1e6);
  std::printf("restore.%s %.1f us\n", spec.name.c_str(), median(restore) * 1e6);
  std::printf("reset_everything.%s %.1f us\n", spec.name.c_str(), median(reset) * 1e6);
  return 0;
}
