#include "macsim/sim_core/world.h"

#include <ode/ode.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "macsim/sim_core/world_loader.h"
#include "ode_support.h"

namespace macsim {

namespace detail {

namespace {
void quiet_message(int, const char*, va_list) {
  // ODE's "LCP internal error, s <= 0" messages are harmless solver notes in contact piles.
}
}  // namespace

void ensure_ode_ready() {
  static const bool initialized = [] {
    dInitODE2(0);
    dSetMessageHandler(&quiet_message);
    return true;
  }();
  (void)initialized;
  thread_local const bool thread_ready = dAllocateODEDataForThread(dAllocateMaskAll) != 0;
  (void)thread_ready;
}

}  // namespace detail

using detail::GeomTag;

namespace {
constexpr int kMaxContacts = 8;
constexpr int kGroundOwner = -2;
}  // namespace

World::World(WorldSpec spec) : spec_(std::move(spec)) {
  detail::ensure_ode_ready();
  dRandSetSeed(spec_.physics.seed);
  world_ = dWorldCreate();
  const auto& g = spec_.physics.gravity;
  dWorldSetGravity(world_, g.x(), g.y(), g.z());
  dWorldSetERP(world_, spec_.physics.erp);
  dWorldSetCFM(world_, spec_.physics.cfm);
  dWorldSetQuickStepNumIterations(world_, spec_.physics.solver_iterations);
  dWorldSetContactSurfaceLayer(world_, 0.001);
  // Each world gets its own threading implementation: ODE's shared default is not safe when
  // two worlds step at once (see the research notes).
  auto impl = dThreadingAllocateSelfThreadedImplementation();
  dWorldSetStepThreadingImplementation(world_, dThreadingImplementationGetFunctions(impl), impl);
  threading_ = impl;
  space_ = dHashSpaceCreate(nullptr);
  contact_group_ = dJointGroupCreate(0);

  if (spec_.ground) {
    ground_ = dCreatePlane(space_, 0, 0, 1, 0);
    dGeomSetData(ground_, &tags_.emplace_back(GeomTag{kGroundOwner, spec_.ground_friction}));
  }
  int owner = 0;
  for (const auto& object : spec_.objects) add_object(object, owner++);
  for (const auto& robot : spec_.robots) {
    if (robot.type != "kurt3d") {
      throw WorldFileError(robot.source.file, robot.source.line,
                           "unknown robot type '" + robot.type + "' (known: kurt3d)");
    }
    robots_.push_back(std::make_unique<KurtRobot>(world_, space_, robot, owner++));
  }
}

World::~World() {
  robots_.clear();
  for (auto& object : objects_) {
    dGeomDestroy(object.geom);
    if (object.body) dBodyDestroy(object.body);
  }
  if (ground_) dGeomDestroy(ground_);
  dJointGroupDestroy(contact_group_);
  dSpaceDestroy(space_);
  dWorldDestroy(world_);
  dThreadingFreeImplementation(static_cast<dThreadingImplementationID>(threading_));
}

void World::add_object(const ObjectSpec& spec, int owner) {
  WorldObject object{spec, nullptr, nullptr};
  switch (spec.shape) {
    case Shape::Box:
      object.geom = dCreateBox(space_, spec.size.x(), spec.size.y(), spec.size.z());
      break;
    case Shape::Cylinder:
      object.geom = dCreateCylinder(space_, spec.size.x(), spec.size.z());
      break;
    case Shape::Sphere:
      object.geom = dCreateSphere(space_, spec.size.x());
      break;
  }
  dGeomSetData(object.geom, &tags_.emplace_back(GeomTag{owner, spec.friction}));
  dQuaternion q;
  detail::to_ode(spec.pose.orientation, q);
  if (spec.portable) {
    object.body = dBodyCreate(world_);
    dMass mass;
    switch (spec.shape) {
      case Shape::Box:
        dMassSetBox(&mass, spec.density, spec.size.x(), spec.size.y(), spec.size.z());
        break;
      case Shape::Cylinder:
        dMassSetCylinder(&mass, spec.density, 3, spec.size.x(), spec.size.z());
        break;
      case Shape::Sphere:
        dMassSetSphere(&mass, spec.density, spec.size.x());
        break;
    }
    if (spec.mass) dMassAdjust(&mass, *spec.mass);
    dBodySetMass(object.body, &mass);
    dGeomSetBody(object.geom, object.body);
    detail::set_body_pose(object.body, spec.pose);
  } else {
    dGeomSetPosition(object.geom, spec.pose.position.x(), spec.pose.position.y(),
                     spec.pose.position.z());
    dGeomSetQuaternion(object.geom, q);
  }
  objects_.push_back(object);
}

KurtRobot* World::robot(const std::string& name) {
  for (auto& r : robots_) {
    if (r->name() == name) return r.get();
  }
  return nullptr;
}

Pose World::object_pose(const WorldObject& object) const {
  dQuaternion q;
  dGeomGetQuaternion(object.geom, q);
  return {detail::vec(dGeomGetPosition(object.geom)), detail::from_ode(q)};
}

void World::near_callback(void* data, dGeomID a, dGeomID b) {
  auto* self = static_cast<World*>(data);
  const auto* ta = static_cast<const GeomTag*>(dGeomGetData(a));
  const auto* tb = static_cast<const GeomTag*>(dGeomGetData(b));
  if (ta && tb && ta->owner == tb->owner) return;
  dBodyID ba = dGeomGetBody(a);
  dBodyID bb = dGeomGetBody(b);
  if (!ba && !bb) return;  // two static geoms
  if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;

  dContact contacts[kMaxContacts];
  const int n = dCollide(a, b, kMaxContacts, &contacts[0].geom, sizeof(dContact));
  const double mu = std::sqrt((ta ? ta->friction : 1.0) * (tb ? tb->friction : 1.0));
  for (int i = 0; i < n; ++i) {
    dSurfaceParameters& s = contacts[i].surface;
    s.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
    s.mu = mu;
    s.soft_erp = 0.2;
    s.soft_cfm = 1e-5;
    dJointID joint = dJointCreateContact(self->world_, self->contact_group_, &contacts[i]);
    dJointAttach(joint, ba, bb);
  }
  self->contacts_ += n;
}

void World::step() {
  detail::ensure_ode_ready();
  const double now = time();
  for (auto& robot : robots_) robot->before_step(now);
  contacts_ = 0;
  dSpaceCollide(space_, this, &World::near_callback);
  dWorldQuickStep(world_, spec_.physics.step);
  dJointGroupEmpty(contact_group_);
  ++steps_;
  for (auto& robot : robots_) robot->after_step(time());
}

}  // namespace macsim
