#include "raw_ode_world.h"

#include <ode/ode.h>

#include <chrono>
#include <cmath>

#include "macsim/sim_core/kurt_robot.h"
#include "vehicle_layout.h"

namespace macsim::bench {

namespace {

void set_quaternion(dGeomID g, const Eigen::Quaterniond& q, bool offset) {
  dQuaternion dq{q.w(), q.x(), q.y(), q.z()};
  if (offset) {
    dGeomSetOffsetWorldQuaternion(g, dq);
  } else {
    dGeomSetQuaternion(g, dq);
  }
}

}  // namespace

RawOdeWorld::RawOdeWorld(const WorldSpec& spec) {
  dInitODE2(0);
  world_ = dWorldCreate();
  dWorldSetGravity(world_, spec.physics.gravity.x(), spec.physics.gravity.y(),
                   spec.physics.gravity.z());
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
  frictions_.push_back(spec.ground_friction);
  dGeomSetData(dCreatePlane(space_, 0, 0, 1, 0), &frictions_.back());
  for (const auto& o : spec.objects) {
    const MaterialSpec* material = spec.material(o.material);
    add_object(o, material ? material->friction : 1.0);
  }
  for (const auto& j : spec.joints) add_joint(j);
  for (const auto& r : spec.robots) add_robot(r);
  step_ = spec.physics.step;
}

RawOdeWorld::~RawOdeWorld() {
  dJointGroupDestroy(contacts_);
  dSpaceDestroy(space_);
  dWorldDestroy(world_);
}

void RawOdeWorld::step() {
  for (dJointID motor : wheel_motors_) dJointSetHingeParam(motor, dParamVel, wheel_rate_);
  dSpaceCollide(space_, this, &RawOdeWorld::near);
  dWorldQuickStep(world_, step_);
  dJointGroupEmpty(contacts_);
}

void RawOdeWorld::drive(double speed) { wheel_rate_ = speed / wheel_radius_; }

std::vector<Eigen::Vector3d> RawOdeWorld::object_positions() const {
  std::vector<Eigen::Vector3d> out;
  for (const auto& [b, com] : portable_) {
    const dReal* p = dBodyGetPosition(b);
    const dReal* q = dBodyGetQuaternion(b);
    out.push_back(Eigen::Vector3d(p[0], p[1], p[2]) -
                  Eigen::Quaterniond(q[0], q[1], q[2], q[3]) * com);
  }
  return out;
}

Pose RawOdeWorld::robot_pose() const {
  if (!chassis_) return {};
  const dReal* p = dBodyGetPosition(chassis_);
  const dReal* q = dBodyGetQuaternion(chassis_);
  return {{p[0], p[1], p[2]}, Eigen::Quaterniond(q[0], q[1], q[2], q[3])};
}

double RawOdeWorld::kinetic_energy() const {
  double e = 0.0;
  for (const auto& [b, com] : portable_) {
    dMass m;
    dBodyGetMass(b, &m);
    const dReal* v = dBodyGetLinearVel(b);
    e += 0.5 * m.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  return e;
}

void RawOdeWorld::near(void* data, dGeomID a, dGeomID b) {
  auto* self = static_cast<RawOdeWorld*>(data);
  dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
  if (!ba && !bb) return;
  if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;
  if (ba && ba == bb) return;
  dContact c[8];
  const int n = dCollide(a, b, 8, &c[0].geom, sizeof(dContact));
  // Each geom's friction (the robot's: 1), combined as sim_core does: the geometric mean.
  auto mu = [](dGeomID g) {
    const void* f = dGeomGetData(g);
    return f ? *static_cast<const double*>(f) : 1.0;
  };
  const double friction = std::sqrt(mu(a) * mu(b));
  for (int i = 0; i < n; ++i) {
    c[i].surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
    c[i].surface.mu = friction;
    c[i].surface.soft_erp = 0.2;
    c[i].surface.soft_cfm = 1e-5;
    dJointAttach(dJointCreateContact(self->world_, self->contacts_, &c[i]), ba, bb);
  }
}

dGeomID RawOdeWorld::geom(const ComponentSpec& c) {
  switch (c.shape) {
    case Shape::Box:
      return dCreateBox(space_, c.size.x(), c.size.y(), c.size.z());
    case Shape::Cylinder:
      return dCreateCylinder(space_, c.size.x(), c.size.z());
    case Shape::Sphere:
      return dCreateSphere(space_, c.size.x());
  }
  return nullptr;
}

void RawOdeWorld::add_object(const ObjectSpec& o, double friction) {
  // Mass from the components, the body at the centre of mass, as sim_core builds it.
  dMass total;
  dMassSetZero(&total);
  for (const auto& c : o.components) {
    dMass m;
    if (c.shape == Shape::Box) {
      dMassSetBox(&m, o.density, c.size.x(), c.size.y(), c.size.z());
    } else if (c.shape == Shape::Cylinder) {
      dMassSetCylinder(&m, o.density, 3, c.size.x(), c.size.z());
    } else {
      dMassSetSphere(&m, o.density, c.size.x());
    }
    dMatrix3 r;
    const dQuaternion q{c.pose.orientation.w(), c.pose.orientation.x(), c.pose.orientation.y(),
                        c.pose.orientation.z()};
    dQtoR(q, r);
    dMassRotate(&m, r);
    dMassTranslate(&m, c.pose.position.x(), c.pose.position.y(), c.pose.position.z());
    dMassAdd(&total, &m);
  }
  const Eigen::Vector3d com(total.c[0], total.c[1], total.c[2]);
  dBodyID body = nullptr;
  if (o.portable) {
    body = dBodyCreate(world_);
    bodies_[o.name] = body;
    portable_.push_back({body, com});
    dMassTranslate(&total, -com.x(), -com.y(), -com.z());
    dBodySetMass(body, &total);
    const Pose p = o.pose * Pose{com, Eigen::Quaterniond::Identity()};
    dBodySetPosition(body, p.position.x(), p.position.y(), p.position.z());
    const dQuaternion q{p.orientation.w(), p.orientation.x(), p.orientation.y(), p.orientation.z()};
    dBodySetQuaternion(body, q);
  }
  frictions_.push_back(friction);
  for (const auto& c : o.components) {
    dGeomID g = geom(c);
    dGeomSetData(g, &frictions_.back());
    const Pose p = o.pose * c.pose;
    if (body) {
      dGeomSetBody(g, body);
      dGeomSetOffsetWorldPosition(g, p.position.x(), p.position.y(), p.position.z());
    } else {
      dGeomSetPosition(g, p.position.x(), p.position.y(), p.position.z());
    }
    set_quaternion(g, p.orientation, body != nullptr);
  }
}

void RawOdeWorld::add_joint(const JointSpec& j) {
  dBodyID body = bodies_.at(j.body1);
  dBodySetAutoDisableFlag(body, 0);
  dJointID joint;
  if (j.type == JointSpec::Type::Slider) {
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

void RawOdeWorld::add_robot(const RobotSpec& robot) {
  const KurtConfig* config = find_kurt_type(robot.type);
  const VehicleLayout layout = vehicle_layout(config ? *config : KurtConfig{}, robot.pose);
  wheel_radius_ = layout.wheel_radius;
  std::vector<dBodyID> bodies;
  for (const VehiclePart& part : layout.parts) {
    dBodyID body = dBodyCreate(world_);
    dBodySetAutoDisableFlag(body, 0);
    dMass m;
    const ComponentSpec& s = part.shape;
    if (part.inertia.squaredNorm() > 0) {
      dMassSetParameters(&m, part.mass, 0, 0, 0, part.inertia.x(), part.inertia.y(),
                         part.inertia.z(), 0, 0, 0);
    } else if (s.shape == Shape::Cylinder) {
      dMassSetCylinderTotal(&m, part.mass, 3, s.size.x(), s.size.z());
    } else {
      dMassSetBoxTotal(&m, part.mass, s.size.x(), s.size.y(), s.size.z());
    }
    dBodySetMass(body, &m);
    const Pose& p = part.pose;
    dBodySetPosition(body, p.position.x(), p.position.y(), p.position.z());
    dQuaternion q{p.orientation.w(), p.orientation.x(), p.orientation.y(), p.orientation.z()};
    dBodySetQuaternion(body, q);
    dGeomID g = geom(s);
    dGeomSetBody(g, body);
    dGeomSetOffsetPosition(g, s.pose.position.x(), s.pose.position.y(), s.pose.position.z());
    dQuaternion gq{s.pose.orientation.w(), s.pose.orientation.x(), s.pose.orientation.y(),
                   s.pose.orientation.z()};
    dGeomSetOffsetQuaternion(g, gq);
    bodies.push_back(body);
  }
  chassis_ = bodies[0];
  for (const VehicleJoint& j : layout.joints) {
    dJointID joint =
        j.slider ? dJointCreateSlider(world_, nullptr) : dJointCreateHinge(world_, nullptr);
    dJointAttach(joint, bodies[j.child], bodies[j.parent]);
    if (j.slider) {
      dJointSetSliderAxis(joint, j.axis.x(), j.axis.y(), j.axis.z());
      dJointSetSliderParam(joint, dParamLoStop, j.lo);
      dJointSetSliderParam(joint, dParamHiStop, j.hi);
      dJointSetSliderParam(joint, dParamFMax, j.max_force);
    } else {
      dJointSetHingeAnchor(joint, j.anchor.x(), j.anchor.y(), j.anchor.z());
      dJointSetHingeAxis(joint, j.axis.x(), j.axis.y(), j.axis.z());
      if (std::isfinite(j.lo)) dJointSetHingeParam(joint, dParamLoStop, j.lo);
      if (std::isfinite(j.hi)) dJointSetHingeParam(joint, dParamHiStop, j.hi);
      dJointSetHingeParam(joint, dParamFMax, j.max_force);
    }
    if (wheel_motors_.size() < 6) wheel_motors_.push_back(joint);
  }
}

double sleeping_bodies_rate(int n, double step) {
  dInitODE2(0);
  dWorldID world = dWorldCreate();
  dWorldSetGravity(world, 0, 0, -9.81);
  dWorldSetAutoDisableFlag(world, 1);
  dSpaceID space = dSimpleSpaceCreate(nullptr);
  const int side = static_cast<int>(std::ceil(std::sqrt(n)));
  for (int i = 0; i < n; ++i) {
    dGeomID box = dCreateBox(space, 0.1, 0.1, 0.1);
    dBodyID body = dBodyCreate(world);
    dMass m;
    dMassSetBox(&m, 500, 0.1, 0.1, 0.1);
    dBodySetMass(body, &m);
    dBodySetPosition(body, (i % side) * 0.25, (i / side) * 0.25, 0.05);
    dGeomSetBody(box, body);
    dBodyDisable(body);
  }
  using Clock = std::chrono::steady_clock;
  for (int i = 0; i < 100; ++i) dWorldQuickStep(world, step);
  const auto start = Clock::now();
  long steps = 0;
  while (std::chrono::duration<double>(Clock::now() - start).count() < 1.0 || steps < 5) {
    dWorldQuickStep(world, step);
    ++steps;
  }
  const double rate = steps / std::chrono::duration<double>(Clock::now() - start).count();
  dSpaceDestroy(space);
  dWorldDestroy(world);
  return rate;
}

}  // namespace macsim::bench
