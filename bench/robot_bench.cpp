// The robot's sensors and cameras against the same world without them, at a 1 ms step:
// step rates and real-time factors (cameras: every frame due rendered, as macsim does it),
// the sensors' share of the step and their rays per second (from the robots' own time in each
// step), camera frames per second.
// Prints `name value unit` lines.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench_world_arg.h"
#include "macsim/render/camera_rig.h"
#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Setup {
  std::string name;
  bool ranges, laser;
  int camera_width = 0, camera_height = 0;  // 0: no cameras
};

/// The world with its robots of a robot type made for `setup` (sensors on or off).
macsim::WorldSpec spec_for(const macsim::WorldSpec& base, const Setup& setup) {
  macsim::KurtConfig config = *macsim::find_kurt_type("kurt3d");
  config.range_sensors = setup.ranges;
  config.laser = setup.laser ? macsim::LaserMount::Rotating : macsim::LaserMount::None;
  config.rotunit_speed = M_PI / 6;
  macsim::register_kurt_type("bench_" + setup.name, config);
  macsim::WorldSpec spec = base;
  for (auto& robot : spec.robots) robot.type = "bench_" + setup.name;
  return spec;
}

/// What one run measured: steps per wall second, and the wall seconds per sim second the
/// robots' own work took (drive, sensors; World::step_profile()).
struct Run {
  double rate = 0.0;
  double robots = 0.0;
};

/// Steps the world with the robot driving an arc for `seconds` of sim time (and prints the
/// camera frames' shares if `report`).
Run step_rate(const macsim::WorldSpec& spec, const Setup& setup, double seconds, bool report) {
  macsim::World world(spec);
  // As macsim does: one render thread per eye, and when a pair is due while they still
  // render the previous one, the simulation waits (no frame due in sim time is skipped).
  std::vector<std::unique_ptr<macsim::render::CameraRig>> rigs;
  if (setup.camera_width > 0) {
    macsim::render::CameraIntrinsics in;
    in.width = setup.camera_width;
    in.height = setup.camera_height;
    for (auto eye : {macsim::render::Eye::Left, macsim::render::Eye::Right}) {
      rigs.push_back(std::make_unique<macsim::render::CameraRig>(
          "kurt", in, [](const macsim::render::CameraImage&) {},
          std::vector<macsim::render::Eye>{eye}));
    }
  }
  const long steps = static_cast<long>(seconds / world.step_size());
  world.clear_step_profile();
  const long camera_every = static_cast<long>(1.0 / 15 / world.step_size());  // 15 Hz
  long due = 0, waited = 0;
  const auto start = Clock::now();
  for (long i = 0; i < steps; ++i) {
    if (i % 100 == 0) world.robot("kurt")->execute(macsim::robot::Twist{0.3, 0.2}, world.time());
    world.step();
    if (!rigs.empty() && i % camera_every == 0) {
      ++due;
      bool busy = false;
      for (auto& rig : rigs) busy = busy || !rig->idle();
      if (busy) ++waited;
      for (auto& rig : rigs) rig->wait_idle();
      const macsim::Scene scene = macsim::capture_scene(world);
      for (auto& rig : rigs) rig->submit(scene);
    }
  }
  for (auto& rig : rigs) rig->wait_idle();
  const double rate = steps / seconds_since(start);
  const double robots = world.step_profile().robots / seconds;
  if (!rigs.empty() && report) {
    std::printf("camera_frames_rendered.%s %.0f %% of due\n", setup.name.c_str(),
                100.0 * static_cast<double>(rigs[0]->rendered()) / static_cast<double>(due));
    std::printf("camera_frames_waited_for.%s %.0f %% of due\n", setup.name.c_str(),
                100.0 * static_cast<double>(waited) / static_cast<double>(due));
  }
  return {rate, robots};
}

}  // namespace

int main(int argc, char** argv) {
  int exit_code = 0;
  const auto loaded = macsim::bench::world_argument(
      argc, argv,
      "usage: bench_robot [WORLD_FILE]  (default worlds/DemoWorld_v1.xml, from the repo root)",
      "worlds/DemoWorld_v1.xml", exit_code);
  if (!loaded) return exit_code;
  const macsim::WorldSpec& spec = *loaded;
  const double seconds = 10.0;
  const std::vector<Setup> setups = {
      {"no_sensors", false, false},
      {"ir_sonar_100hz", true, false},
      {"ir_sonar_laser_75hz", true, true},
      {"ir_sonar_laser_cameras_320x240_15hz", true, true, 320, 240},
      {"ir_sonar_laser_cameras_640x480_15hz", true, true, 640, 480},
  };
  // Three runs of each set-up, taken in turn so that all see the same machine noise; medians.
  std::vector<macsim::WorldSpec> specs;
  for (const auto& setup : setups) specs.push_back(spec_for(spec, setup));
  std::vector<std::vector<double>> runs(setups.size()), robots(setups.size());
  for (int run = 0; run < 3; ++run) {
    for (std::size_t i = 0; i < setups.size(); ++i) {
      const Run r = step_rate(specs[i], setups[i], seconds, run == 2);
      runs[i].push_back(r.rate);
      robots[i].push_back(r.robots);
    }
  }
  std::vector<double> rates, robot_time;
  for (std::size_t i = 0; i < setups.size(); ++i) {
    rates.push_back(median(runs[i]));
    robot_time.push_back(median(robots[i]));
    std::printf("step_rate.%s %.0f steps/s\n", setups[i].name.c_str(), rates.back());
    std::printf("real_time_factor.%s %.1f x\n", setups[i].name.c_str(), rates.back() * 0.001);
  }
  std::printf("ratio.ir_sonar_laser_over_no_sensors %.3f x (goal >= 0.97)\n", rates[2] / rates[0]);
  // The sensors' cost, from the robots' own time in each step (World::step_profile()): what
  // the set-up with them takes beyond the one without, over the whole step.
  for (std::size_t i : {std::size_t{1}, std::size_t{2}}) {
    std::printf("share.%s.sensors %.2f %% of the step\n", setups[i].name.c_str(),
                100.0 * (robot_time[i] - robot_time[0]) * rates[i] / 1000.0);
  }
  std::printf("robots_time.no_sensors %.2f %% of the step\n",
              100.0 * robot_time[0] * rates[0] / 1000.0);
  // Rays: IR/sonar 8 sensors x 3 rays x 100 frames, laser 181 rays x 75 sweeps per sim second.
  std::printf("ir_sonar_rays_per_second %.0f rays/s\n",
              8 * 3 * 100 / (robot_time[1] - robot_time[0]));
  std::printf("laser_rays_per_second %.0f rays/s\n", 181 * 75 / (robot_time[2] - robot_time[1]));

  macsim::World world(spec);
  // Cameras: stereo pairs per second on one thread.
  for (auto [w, h] : {std::pair{320, 240}, std::pair{640, 480}}) {
    macsim::render::OffscreenRenderer renderer(w, h);
    macsim::render::CameraIntrinsics in;
    in.width = w;
    in.height = h;
    const auto scene = macsim::capture_scene(world);
    for (int i = 0; i < 5; ++i) renderer.render(scene, scene.robots[0].left_camera, in);
    const auto t0 = Clock::now();
    const int frames = 60;
    for (int i = 0; i < frames; ++i) renderer.render(scene, scene.robots[0].left_camera, in);
    std::printf("camera_fps.%dx%d %.0f frames/s\n", w, h, frames / seconds_since(t0));
  }
  return 0;
}
