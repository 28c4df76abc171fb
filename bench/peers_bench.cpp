// sim_core beside raw ODE and MuJoCo 2.2.2 on the same scenes: the six-wheel vehicle driving,
// piles of 10 / 100 / 1000 objects falling and resting, the demo room with the robot pushing
// a can. Runs alternate between the engines so all see the same machine noise. Prints steps/s,
// the ratios, and per scene a fidelity check so speed is never bought with wrong physics.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "macsim/sim_core/kurt_robot.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "mujoco_world.h"
#include "raw_ode_world.h"
#include "scenes.h"

namespace {

using macsim::Pose;
using macsim::WorldSpec;
using macsim::bench::PeerEngine;
using Clock = std::chrono::steady_clock;

/// sim_core's World behind the peers' interface (robot driven through its twist command).
class SimCoreEngine : public PeerEngine {
 public:
  explicit SimCoreEngine(const WorldSpec& spec) : world_(spec) {
    for (const auto& o : spec.objects) {
      if (o.portable) ids_.push_back(*world_.objects().find_object(o.name));
    }
  }
  void step() override {
    if (speed_ != 0.0 && world_.steps() % 100 == 0) {
      for (auto& r : world_.robots()) r->execute(macsim::robot::Twist{speed_, 0.0}, world_.time());
    }
    world_.step();
  }
  void drive(double speed) override { speed_ = speed; }
  std::vector<Eigen::Vector3d> object_positions() const override {
    std::vector<Eigen::Vector3d> out;
    for (auto id : ids_) out.push_back(world_.objects().object_state(id).value.pose.position);
    return out;
  }
  Pose robot_pose() const override {
    return world_.robots().empty() ? Pose{} : world_.robots()[0]->base_link_pose();
  }
  double kinetic_energy() const override {
    double e = 0.0;
    for (auto id : ids_) {
      e += 0.5 * world_.objects().object_mass(id).value *
           world_.objects().object_state(id).value.linear_velocity.squaredNorm();
    }
    return e;
  }

 private:
  macsim::World world_;
  std::vector<macsim::ObjectId> ids_;
  double speed_ = 0.0;
};

enum class Engine { RawOde, SimCore, Mujoco };
constexpr Engine kEngines[] = {Engine::RawOde, Engine::SimCore, Engine::Mujoco};
const char* engine_name(Engine e) {
  return e == Engine::RawOde ? "raw_ode" : e == Engine::SimCore ? "sim_core" : "mujoco";
}

/// What a run leaves to check: poses at the end and 0.25 s before it, the energy at the end.
struct Outcome {
  double steps_per_second = 0.0;
  std::vector<Eigen::Vector3d> objects, objects_before_end;
  Pose robot_start, robot_end;
  double kinetic_energy = 0.0;
  int overflows = 0;
};

struct Scene {
  std::string name;
  WorldSpec spec;
  double seconds = 2.0;               ///< sim time of a run
  double drive = 0.0;                 ///< m/s commanded to the robot
  std::string integrator;             ///< MuJoCo's
  std::vector<Eigen::Vector3d> rest;  ///< where the objects should end (piles)
  int watched = -1;                   ///< portable object whose travel is checked (the pushed can)
  bool multiccd = false;              ///< MuJoCo's: several contacts between convex shapes
};

std::unique_ptr<PeerEngine> make(Engine e, const Scene& scene) {
  switch (e) {
    case Engine::RawOde:
      return std::make_unique<macsim::bench::RawOdeWorld>(scene.spec);
    case Engine::SimCore:
      return std::make_unique<SimCoreEngine>(scene.spec);
    case Engine::Mujoco:
      return std::make_unique<macsim::bench::MujocoWorld>(
          scene.spec, macsim::bench::MujocoOptions{scene.integrator, scene.multiccd});
  }
  return nullptr;
}

Outcome run(Engine e, const Scene& scene) {
  auto engine = make(e, scene);
  engine->drive(scene.drive);
  Outcome out;
  out.robot_start = engine->robot_pose();
  const double dt = scene.spec.physics.step;
  const long steps = std::lround(scene.seconds / dt);
  const long mark = steps - std::lround(0.25 / dt);
  Clock::duration reading{};  // the bench's read-out is not the engine's time
  const auto start = Clock::now();
  for (long i = 0; i < steps; ++i) {
    engine->step();
    if (i + 1 == mark) {
      const auto t = Clock::now();
      out.objects_before_end = engine->object_positions();
      reading += Clock::now() - t;
    }
  }
  out.steps_per_second =
      steps / std::chrono::duration<double>(Clock::now() - start - reading).count();
  out.objects = engine->object_positions();
  out.robot_end = engine->robot_pose();
  out.kinetic_energy = engine->kinetic_energy();
  out.overflows = engine->overflows();
  return out;
}

double yaw(const Pose& p) {
  const Eigen::Vector3d x = p.orientation * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void print_fidelity(const Scene& scene, Engine e, const Outcome& o) {
  const std::string key = "fidelity." + scene.name + "." + engine_name(e);
  if (!scene.spec.robots.empty()) {
    const Eigen::Vector3d d = o.robot_end.position - o.robot_start.position;
    const double heading = yaw(o.robot_start);
    const double along = d.x() * std::cos(heading) + d.y() * std::sin(heading);
    const double across = -d.x() * std::sin(heading) + d.y() * std::cos(heading);
    std::printf("%s.robot_travel %.3f m (commanded %.3f)\n", key.c_str(), along,
                scene.drive * scene.seconds);
    std::printf("%s.robot_sideways %.4f m\n", key.c_str(), across);
    std::printf("%s.robot_yaw_change %.2f deg\n", key.c_str(),
                std::remainder(yaw(o.robot_end) - heading, 2 * M_PI) * 180 / M_PI);
  }
  if (scene.watched >= 0) {
    const Eigen::Vector3d start = scene.spec.objects[scene.watched].pose.position;
    int k = 0;  // the watched object's index among the portable ones
    for (int i = 0; i < scene.watched; ++i) k += scene.spec.objects[i].portable ? 1 : 0;
    const Eigen::Vector3d end = o.objects[k];
    std::printf("%s.can_pushed %.3f m\n", key.c_str(), (end - start).head<2>().norm());
    std::printf("%s.can_height_change %.4f m (0: upright)\n", key.c_str(), end.z() - start.z());
  }
  if (!scene.rest.empty()) {
    double sum = 0.0, worst = 0.0, drift = 0.0;
    for (std::size_t i = 0; i < o.objects.size(); ++i) {
      const double err = (o.objects[i] - scene.rest[i]).norm();
      sum += err * err;
      worst = std::max(worst, err);
      drift = std::max(drift, (o.objects[i] - o.objects_before_end[i]).norm());
    }
    std::printf("%s.rest_pose_error_rms %.5f m\n", key.c_str(), std::sqrt(sum / o.objects.size()));
    std::printf("%s.rest_pose_error_max %.5f m\n", key.c_str(), worst);
    std::printf("%s.rest_drift_last_0.25s %.6f m\n", key.c_str(), drift);
  }
  std::printf("%s.kinetic_energy_end %.3g J\n", key.c_str(), o.kinetic_energy);
  if (o.overflows > 0) {
    std::printf("%s.steps_with_contacts_dropped %d steps (buffers full)\n", key.c_str(),
                o.overflows);
  }
}

/// The scenes by name, each built when it runs (the demo room reads worlds/ from the cwd).
std::vector<std::pair<std::string, std::function<Scene()>>> scenes() {
  // The robot: the KURT3D without sensors (physics only, in every engine).
  macsim::KurtConfig bare = *macsim::find_kurt_type("kurt3d");
  bare.range_sensors = false;
  bare.laser = macsim::LaserMount::None;
  macsim::register_kurt_type("bench_peers_kurt", bare);
  std::vector<std::pair<std::string, std::function<Scene()>>> out;
  // The vehicle driving straight on an empty floor.
  out.emplace_back("vehicle", [] {
    Scene s{"vehicle", macsim::bench::empty_world("vehicle"), 5.0, 0.3, "implicit", {}, -1};
    macsim::RobotSpec robot;
    robot.name = "kurt";
    robot.type = "bench_peers_kurt";
    s.spec.robots.push_back(robot);
    return s;
  });
  // 300: the largest of these piles whose contacts fit in MuJoCo 2.2.2's buffer (see README).
  for (int n : {10, 100, 300, 1000}) {
    const std::string name = "pile_" + std::to_string(n);
    out.emplace_back(name, [n, name] {
      Scene s{name, {}, n >= 1000 ? 1.0 : 2.0, 0.0, "Euler", {}, -1};
      s.spec = macsim::bench::pile(n, &s.rest);
      s.multiccd = true;
      return s;
    });
  }
  // The demo room: the robot 0.5 m behind a tin can (0.25 m from its bumper), pushing it 4 s.
  out.emplace_back("demo_push_can", [] {
    Scene s{"demo_push_can",
            macsim::load_world_file("worlds/DemoWorld_v1.xml"),
            4.0,
            0.3,
            "implicit",
            {},
            -1};
    for (auto& r : s.spec.robots) r.type = "bench_peers_kurt";
    const Pose footprint = s.spec.robots.at(0).pose;
    for (std::size_t i = 0; i < s.spec.objects.size(); ++i) {
      if (s.spec.objects[i].name.find("can_00") == std::string::npos) continue;
      s.spec.objects[i].pose.position =
          footprint.position + footprint.orientation * Eigen::Vector3d(0.5, 0, 0);
      s.watched = static_cast<int>(i);
    }
    return s;
  });
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 3;
  std::string only;
  std::vector<Engine> engines(std::begin(kEngines), std::end(kEngines));
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::printf(
          "usage: bench_peers [--repeats N] [--scene NAME] [--engine NAME]  (from the repo root)\n"
          "sim_core, raw ODE and MuJoCo %s on the same scenes, runs alternating; prints\n"
          "steps/s, ratios and fidelity checks as `name value unit` lines. Scenes: vehicle,\n"
          "pile_10, pile_100, pile_300, pile_1000, demo_push_can (default: all). --engine\n"
          "raw_ode, sim_core or mujoco runs that one alone (for profiling; no ratios).\n",
          macsim::bench::mujoco_version().c_str());
      return 0;
    }
    if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) {
      char* end = nullptr;
      repeats = static_cast<int>(std::strtol(argv[++i], &end, 10));
      if (*end == '\0' && repeats >= 1) continue;
    }
    if (!std::strcmp(argv[i], "--engine") && i + 1 < argc) {
      const std::string name = argv[++i];
      std::erase_if(engines, [&](Engine e) { return name != engine_name(e); });
      if (engines.size() == 1) continue;
      std::fprintf(stderr, "bench_peers: unknown engine '%s' (see --help)\n", name.c_str());
      return 2;
    }
    if (!std::strcmp(argv[i], "--scene") && i + 1 < argc) {
      only = argv[++i];
      continue;
    }
    std::fprintf(stderr, "bench_peers: bad argument '%s' (see --help)\n", argv[i]);
    return 2;
  }
  auto all = scenes();
  if (!only.empty()) {
    std::erase_if(all, [&](const auto& scene) { return scene.first != only; });
    if (all.empty()) {
      std::fprintf(stderr, "bench_peers: unknown scene '%s' (see --help)\n", only.c_str());
      return 2;
    }
  }
  std::printf("mujoco_version %s\n", macsim::bench::mujoco_version().c_str());
  for (const auto& [name, make_scene] : all) {
    Scene scene;
    try {
      scene = make_scene();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_peers: %s: %s (run it from the repository root)\n", name.c_str(),
                   e.what());
      return 1;
    }
    std::vector<double> rates[3];
    Outcome last[3];
    for (int r = 0; r < repeats; ++r) {
      for (Engine e : engines) {
        last[static_cast<int>(e)] = run(e, scene);
        rates[static_cast<int>(e)].push_back(last[static_cast<int>(e)].steps_per_second);
      }
    }
    double rate[3];
    for (Engine e : engines) {
      rate[static_cast<int>(e)] = median(rates[static_cast<int>(e)]);
      std::printf("step_rate.%s.%s %.0f steps/s\n", scene.name.c_str(), engine_name(e),
                  rate[static_cast<int>(e)]);
    }
    if (engines.size() == 3) {
      const double raw = rate[0], core = rate[1], mujoco = rate[2];
      std::printf("cost_ratio.%s.sim_core_over_raw_ode %.3f x\n", scene.name.c_str(), raw / core);
      std::printf("speed_ratio.%s.sim_core_over_mujoco %.2f x\n", scene.name.c_str(),
                  core / mujoco);
      std::printf("speed_ratio.%s.raw_ode_over_mujoco %.2f x\n", scene.name.c_str(), raw / mujoco);
    }
    for (Engine e : engines) print_fidelity(scene, e, last[static_cast<int>(e)]);
    std::fflush(stdout);
  }
  return 0;
}
