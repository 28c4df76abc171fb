// The world whose snapshots fuzz_snapshot feeds back to restore(), shared with the seeds: a
// KURT3D holding a can with its magnet, a rover, a small pile of boxes that falls asleep.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"

namespace macsim::fuzz {

/// The scene as loaded (the robots only: the objects are spawned, as a run spawns them).
inline std::unique_ptr<World> snapshot_scene() {
  auto made = std::make_unique<World>(load_world_string(R"(<WORLD>
      <ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT>
      <ROBOT><ID>rover</ID><TYPE>diff_drive</TYPE><POS>0,2,0</POS></ROBOT></WORLD>)",
                                                        "snapshot_scene.xml"));
  World& world = *made;
  ObjectSpec can;
  can.name = "can";
  can.components = {
      {Shape::Cylinder, {0.033, 0, 0.115}, {{0, 0, 0.0575}, {1, 0, 0, 0}}, {1, 0, 0, 1}, ""},
      {Shape::Sphere, {0.02, 0, 0}, {{0, 0, 0.115}, {1, 0, 0, 0}}, {1, 1, 1, 1}, ""}};
  can.pose.position = {0.55, 0, 0};  // under the magnet
  can.density = 190;
  can.magnetizable = true;
  world.edit().create_object(can);
  for (int i = 0; i < 4; ++i) {
    ObjectSpec box;
    box.name = "box_" + std::to_string(i);
    box.components = {{Shape::Box, {0.1, 0.1, 0.1}, {}, {0, 0, 1, 1}, ""}};
    box.pose.position = {1.2 + 0.1 * (i % 2), -0.05 + 0.1 * (i / 2 % 2), 0.05};
    world.edit().create_object(box);
  }
  return made;
}

/// Snapshots of the scene along a run: at rest, the pile asleep, the can held and hoisted.
inline std::vector<WorldSnapshot> snapshot_scene_moments(World& world) {
  auto run = [&](double seconds) {
    for (int i = 0; i < static_cast<int>(seconds / world.step_size()); ++i) world.step();
  };
  std::vector<WorldSnapshot> moments{world.snapshot()};
  RobotModel& kurt = *world.robot("kurt");
  world.robot("rover")->execute(robot::Twist{0.2, 0.5}, world.time());
  run(0.5);
  moments.push_back(world.snapshot());
  kurt.execute(robot::CraneTarget{0.0, 0.0, 0.2}, world.time());
  run(2.0);
  kurt.execute(robot::MagnetSwitch{true}, world.time());
  run(0.2);
  kurt.execute(robot::CraneTarget{0.0, 0.0, 0.0}, world.time());
  run(1.0);
  moments.push_back(world.snapshot());
  return moments;
}

}  // namespace macsim::fuzz
