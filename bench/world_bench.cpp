// sim_core step rate against raw ODE on the same bodies and geoms, step rate for 10 / 100 /
// 1000 portable objects, and the cost of snapshot, restore and reset. Prints `name value unit`.
#include <ode/ode.h>

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

namespace {

using Clock = std::chrono::steady_clock;
using macsim::Pose;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// The baseline: the same world built with plain ODE calls, stepped with a minimal loop
/// (collide, QuickStep, empty contacts) and the robot's six wheel motors set each step.
class RawOdeWorld {
 public:
  explicit RawOdeWorld(const macsim::WorldSpec& spec) {
    world_ = dWorldCreate();
    dWorldSetGravity(world_, 0, 0, -9.81);
    dWorldSetERP(world_, spec.physics.erp);
    dWorldSetCFM(world_, spec.physics.cfm);
    dWorldSetQuickStepNumIterations(world_, spec.physics.solver_iterations);
    dWorldSetContactSurfaceLayer(world_, 0.001);
    dWorldSetContactMaxCorrectingVel(world_, 1.0);
    dWorldSetAutoDisableFlag(world_, 1);  // the same sleeping as sim_core
    dWorldSetAutoDisableLinearThreshold(world_, 0.005);
    dWorldSetAutoDisableAngularThreshold(world_, 0.01);
    dWorldSetAutoDisableSteps(world_, 50);
    dWorldSetAutoDisableTime(world_, 0);
    space_ = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ);  // as sim_core
    contacts_ = dJointGroupCreate(0);
    dCreatePlane(space_, 0, 0, 1, 0);
    for (const auto& o : spec.objects) add_object(o);
    for (const auto& j : spec.joints) add_joint(j);
    for (const auto& r : spec.robots) add_robot(r.pose);
    step_ = spec.physics.step;
  }
  ~RawOdeWorld() {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);
    dWorldDestroy(world_);
  }
  void step() {
    for (std::size_t i = 0; i < hinges_.size(); ++i)
      dJointSetHingeParam(hinges_[i], dParamVel, 5.0);
    dSpaceCollide(space_, this, &RawOdeWorld::near);
    dWorldQuickStep(world_, step_);
    dJointGroupEmpty(contacts_);
  }

 private:
  static void near(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<RawOdeWorld*>(data);
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (!ba && !bb) return;
    if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;
    if (ba && ba == bb) return;
    dContact c[8];
    const int n = dCollide(a, b, 8, &c[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
      c[i].surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
      c[i].surface.mu = 1.0;
      c[i].surface.soft_erp = 0.2;
      c[i].surface.soft_cfm = 1e-5;
      dJointAttach(dJointCreateContact(self->world_, self->contacts_, &c[i]), ba, bb);
    }
  }
  dGeomID geom(const macsim::ComponentSpec& c) {
    switch (c.shape) {
      case macsim::Shape::Box:
        return dCreateBox(space_, c.size.x(), c.size.y(), c.size.z());
      case macsim::Shape::Cylinder:
        return dCreateCylinder(space_, c.size.x(), c.size.z());
      case macsim::Shape::Sphere:
        return dCreateSphere(space_, c.size.x());
    }
    return nullptr;
  }
  void add_object(const macsim::ObjectSpec& o) {
    dBodyID body = o.portable ? dBodyCreate(world_) : nullptr;
    if (body) {
      bodies_[o.name] = body;
      dMass m;
      dMassSetBoxTotal(&m, o.mass(), 0.1, 0.1, 0.1);
      dBodySetMass(body, &m);
      dBodySetPosition(body, o.pose.position.x(), o.pose.position.y(), o.pose.position.z());
    }
    for (const auto& c : o.components) {
      dGeomID g = geom(c);
      const Pose p = o.pose * c.pose;
      dQuaternion q{p.orientation.w(), p.orientation.x(), p.orientation.y(), p.orientation.z()};
      if (body) {
        dGeomSetBody(g, body);
        dGeomSetOffsetWorldPosition(g, p.position.x(), p.position.y(), p.position.z());
        dGeomSetOffsetWorldQuaternion(g, q);
      } else {
        dGeomSetPosition(g, p.position.x(), p.position.y(), p.position.z());
        dGeomSetQuaternion(g, q);
      }
    }
  }
  void add_joint(const macsim::JointSpec& j) {
    dBodyID body = bodies_.at(j.body1);
    dBodySetAutoDisableFlag(body, 0);
    dJointID joint;
    if (j.type == macsim::JointSpec::Type::Slider) {
      joint = dJointCreateSlider(world_, nullptr);
      dJointAttach(joint, body, nullptr);
      dJointSetSliderAxis(joint, j.axis.x(), j.axis.y(), j.axis.z());
      dJointSetSliderParam(joint, dParamLoStop, j.lo);
      dJointSetSliderParam(joint, dParamHiStop, j.hi);
      dJointSetSliderParam(joint, dParamFMax, j.max_force);
      dJointSetSliderParam(joint, dParamVel, j.velocity);
    } else {
      joint = dJointCreateHinge(world_, nullptr);
      dJointAttach(joint, body, nullptr);
      dJointSetHingeAnchor(joint, j.anchor.x(), j.anchor.y(), j.anchor.z());
      dJointSetHingeAxis(joint, j.axis.x(), j.axis.y(), j.axis.z());
      dJointSetHingeParam(joint, dParamFMax, j.max_force);
      dJointSetHingeParam(joint, dParamVel, j.velocity);
    }
  }
  void add_robot(const Pose& pose) {
    dBodyID chassis = dBodyCreate(world_);
    dBodySetAutoDisableFlag(chassis, 0);
    dMass m;
    dMassSetBoxTotal(&m, 15.6, 0.43, 0.325, 0.215);
    dBodySetMass(chassis, &m);
    const Eigen::Vector3d c = pose.position + Eigen::Vector3d(0, 0, 0.127);
    dBodySetPosition(chassis, c.x(), c.y(), c.z());
    dGeomID box = dCreateBox(space_, 0.43, 0.325, 0.215);
    dGeomSetBody(box, chassis);
    dGeomSetOffsetPosition(box, 0, 0, 0.04);
    for (int i = 0; i < 6; ++i) {
      const double x = (i % 3 - 1) * 0.14, y = i < 3 ? 0.14 : -0.14;
      dBodyID wheel = dBodyCreate(world_);
      dBodySetAutoDisableFlag(wheel, 0);
      dMassSetCylinderTotal(&m, 0.3, 3, 0.0603, 0.035);
      dBodySetMass(wheel, &m);
      dBodySetPosition(wheel, pose.position.x() + x, pose.position.y() + y, 0.0603);
      dMatrix3 r;
      dRFromAxisAndAngle(r, 1, 0, 0, -M_PI / 2);
      dBodySetRotation(wheel, r);
      dGeomID g = dCreateCylinder(space_, 0.0603, 0.035);
      dGeomSetBody(g, wheel);
      dJointID h = dJointCreateHinge(world_, nullptr);
      dJointAttach(h, wheel, chassis);
      dJointSetHingeAnchor(h, pose.position.x() + x, pose.position.y() + y, 0.0603);
      dJointSetHingeAxis(h, 0, 1, 0);
      dJointSetHingeParam(h, dParamFMax, 4.0);
      hinges_.push_back(h);
    }
    // The crane: turret on a vertical hinge, boom on a horizontal one, magnet on a slider.
    dBodyID turret = add_box(pose.position + Eigen::Vector3d(0.05, 0, 0.30), 1.0, {0.1, 0.1, 0.05});
    dBodyID boom = add_box(pose.position + Eigen::Vector3d(0.30, 0, 0.327), 0.5, {0.5, 0.04, 0.04});
    dBodyID magnet =
        add_box(pose.position + Eigen::Vector3d(0.55, 0, 0.29), 0.2, {0.07, 0.07, 0.03});
    const Eigen::Vector3d p = pose.position;
    add_motor(dJointCreateHinge(world_, nullptr), turret, chassis,
              p + Eigen::Vector3d(0.05, 0, 0.275), {0, 0, 1});
    add_motor(dJointCreateHinge(world_, nullptr), boom, turret, p + Eigen::Vector3d(0.05, 0, 0.327),
              {0, -1, 0});
    dJointID slider = dJointCreateSlider(world_, nullptr);
    dJointAttach(slider, magnet, boom);
    dJointSetSliderAxis(slider, 0, 0, -1);
    dJointSetSliderParam(slider, dParamFMax, 7.0);
  }
  dBodyID add_box(const Eigen::Vector3d& at, double mass, const Eigen::Vector3d& size) {
    dBodyID body = dBodyCreate(world_);
    dBodySetAutoDisableFlag(body, 0);
    dMass m;
    dMassSetBoxTotal(&m, mass, size.x(), size.y(), size.z());
    dBodySetMass(body, &m);
    dBodySetPosition(body, at.x(), at.y(), at.z());
    dGeomID g = dCreateBox(space_, size.x(), size.y(), size.z());
    dGeomSetBody(g, body);
    return body;
  }
  void add_motor(dJointID hinge, dBodyID a, dBodyID b, const Eigen::Vector3d& anchor,
                 const Eigen::Vector3d& axis) {
    dJointAttach(hinge, a, b);
    dJointSetHingeAnchor(hinge, anchor.x(), anchor.y(), anchor.z());
    dJointSetHingeAxis(hinge, axis.x(), axis.y(), axis.z());
    dJointSetHingeParam(hinge, dParamFMax, 5.0);
  }

  dWorldID world_;
  dSpaceID space_;
  dJointGroupID contacts_;
  std::vector<dJointID> hinges_;
  std::map<std::string, dBodyID> bodies_;
  double step_ = 0.001;
};

/// Steps per second over `seconds` of sim time, after a 0.5 s warm-up.
double rate(const std::function<void()>& step, double dt, double seconds) {
  for (int i = 0; i < static_cast<int>(0.5 / dt); ++i) step();
  const long steps = static_cast<long>(seconds / dt);
  const auto start = Clock::now();
  for (long i = 0; i < steps; ++i) step();
  return steps / seconds_since(start);
}

macsim::WorldSpec pile(int n) {
  std::string xml = "<WORLD><NAME>pile_" + std::to_string(n) + "</NAME>";
  const int side = static_cast<int>(std::ceil(std::sqrt(n)));
  for (int i = 0; i < n; ++i) {
    const double x = (i % side) * 0.25, y = (i / side) * 0.25;
    const bool sphere = i % 2;
    xml += "<OBJECT><ID>o" + std::to_string(i) + "</ID><SHAPE>" + (sphere ? "SPHERE" : "BOX") +
           "</SHAPE>" + (sphere ? "<RADIUS>0.06</RADIUS>" : "<DIMS>0.1,0.1,0.1</DIMS>") + "<POS>" +
           std::to_string(x) + "," + std::to_string(y) + ",0.2</POS></OBJECT>";
  }
  return macsim::load_world_string(xml + "</WORLD>", "pile.xml");
}

/// `n` boxes of 10 cm on a grid 0.25 m apart, resting on the floor.
macsim::WorldSpec resting_boxes(int n) {
  macsim::WorldSpec spec;
  spec.name = "resting_boxes_" + std::to_string(n);
  macsim::MaterialSpec fallback;
  fallback.name = "default";
  spec.materials.push_back(fallback);
  const int side = static_cast<int>(std::ceil(std::sqrt(n)));
  for (int i = 0; i < n; ++i) {
    spec.objects.push_back(macsim::box_object(
        {(i % side) * 0.25 - side * 0.125, (i / side) * 0.25 - side * 0.125, 0.0499},
        {0.1, 0.1, 0.1}));
    spec.objects.back().name = "box_" + std::to_string(i);
  }
  return spec;
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
            for (auto& r : world.robots()) r->command_twist(0.3, 0.0, world.time());
          }
          world.step();
        },
        world.step_size(), 2.0));
    RawOdeWorld raw(spec);
    raw_rates.push_back(rate([&] { raw.step(); }, 0.001, 2.0));
  }
  const double core = median(core_rates), raw = median(raw_rates);
  std::printf("step_rate.%s.sim_core %.0f steps/s\n", spec.name.c_str(), core);
  std::printf("step_rate.%s.raw_ode %.0f steps/s\n", spec.name.c_str(), raw);
  std::printf("cost_ratio.%s.sim_core_over_raw_ode %.3f x\n", spec.name.c_str(), raw / core);

  // 2. Many portable objects.
  for (int n : {10, 100, 1000}) {
    macsim::World world(pile(n));
    const double seconds = n >= 1000 ? 0.5 : 2.0;
    std::printf("step_rate.objects_%d %.0f steps/s\n", n,
                rate([&] { world.step(); }, world.step_size(), seconds));
  }

  // 2b. Scale: grids of boxes resting on the floor (asleep once settled); the cost should grow
  // about linearly with their number.
  std::map<int, double> resting;
  for (int n : {1000, 5000, 20000}) {
    macsim::World world(resting_boxes(n));
    for (int i = 0; i < 200; ++i) world.step();  // settle: they fall asleep
    const auto start = Clock::now();
    int steps = 0;
    while (seconds_since(start) < 1.0 || steps < 5) {
      world.step();
      ++steps;
    }
    resting[n] = steps / seconds_since(start);
    std::printf("step_rate.resting_boxes_%d %.1f steps/s\n", n, resting[n]);
  }
  std::printf("scale.resting_boxes_20000_over_5000 %.3f x (linear: 0.25)\n",
              resting[20000] / resting[5000]);

  // 3. Trials: snapshot, restore, reset.
  macsim::World world(spec);
  for (int i = 0; i < 500; ++i) world.step();
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
    world.restore(s);
    restore.push_back(seconds_since(t));
    t = Clock::now();
    world.reset(macsim::ResetScope::Everything);
    reset.push_back(seconds_since(t));
  }
  std::printf("state.%s %.1f us\n", spec.name.c_str(), median(state) * 1e6);
  std::printf("state_hash.%s %.1f us\n", spec.name.c_str(), median(hash) * 1e6);
  std::printf("snapshot.%s %.1f us\n", spec.name.c_str(), median(snap) * 1e6);
  std::printf("restore.%s %.1f us\n", spec.name.c_str(), median(restore) * 1e6);
  std::printf("reset_everything.%s %.1f us\n", spec.name.c_str(), median(reset) * 1e6);
  return 0;
}
