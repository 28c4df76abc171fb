// Helpers for sim_core tests: load shipped worlds, step for a while, make simple objects.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "support/child_process.h"

namespace macsim::test {

/// A shipped world file, e.g. "DemoWorld_v1.xml".
inline WorldSpec shipped_world(const std::string& file) {
  return load_world_file(source("worlds/" + file));
}

/// The small room the runner's and the session's tests use.
inline WorldSpec small_room() { return shipped_world("small_room.xml"); }

/// The heading of a pose about the z axis, rad.
inline double yaw_of(const Pose& p) {
  const Eigen::Vector3d x = p.orientation * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

/// The number of the world's steps in `seconds` of sim time.
inline long steps_in(const World& world, double seconds) {
  return static_cast<long>(std::llround(seconds / world.step_size()));
}

/// Steps `seconds` of sim time.
inline void run_for(World& world, double seconds) {
  for (long i = 0, steps = steps_in(world, seconds); i < steps; ++i) world.step();
}

/// Steps `seconds` of sim time driving ROBOT at (linear m/s, angular rad/s), the twist sent
/// through the robot's command interface every 0.1 s, as a controller sends it.
inline void drive(World& world, const std::string& robot, double linear, double angular,
                  double seconds) {
  RobotModel& model = *world.robot(robot);
  const long repeat = std::max(1L, steps_in(world, 0.1));
  for (long i = 0, steps = steps_in(world, seconds); i < steps; ++i) {
    if (i % repeat == 0) model.execute(macsim::robot::Twist{linear, angular}, world.time());
    world.step();
  }
}

/// A pose at (x, y, z) without rotation.
inline Pose at(double x, double y, double z) {
  return {{x, y, z}, Eigen::Quaterniond::Identity()};
}

/// A one-component object of the given shape and size at `position`.
inline ObjectSpec primitive(Shape shape, const Eigen::Vector3d& size, const Eigen::Vector3d& position,
                            bool portable = true) {
  switch (shape) {
    case Shape::Box: return box_object(position, size, portable);
    case Shape::Cylinder: return cylinder_object(position, size.x(), size.z(), portable);
    case Shape::Sphere: break;
  }
  return sphere_object(position, size.x(), portable);
}

/// The id of a named object, failing the test if it is missing.
inline ObjectId id_of(const World& world, const std::string& name) {
  auto id = world.objects().find_object(name);
  if (!id) throw std::runtime_error("no object named " + name);
  return *id;
}

/// Height of an object's frame once it has settled.
inline double settled_z(World& world, ObjectId id, double seconds = 1.5) {
  run_for(world, seconds);
  return world.objects().object_state(id).value.pose.position.z();
}

/// A fresh temporary directory for test files.
inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             ("macsim-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

}  // namespace macsim::test
