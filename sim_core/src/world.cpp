// World: building ODE from the description, stepping, contacts, doors, stability.
#include "macsim/sim_core/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <unordered_set>

#include "broad_phase.h"
#include "macsim/sim_core/world_bounds.h"
#include "macsim/sim_core/world_loader.h"
#include "world_internal.h"

namespace macsim {

namespace detail {

namespace {
void quiet_message(int, const char*, va_list) {
  // ODE's "LCP internal error, s <= 0" messages are harmless solver notes in contact piles.
}

[[noreturn]] void throw_ode_error(int number, const char* format, va_list arguments) {
  char text[512];
  std::vsnprintf(text, sizeof text, format, arguments);
  throw OdeError("ODE error " + std::to_string(number) + ": " + text);
}
}  // namespace

void ensure_ode_ready() {
  static const bool initialized = [] {
    dInitODE2(0);
    dSetMessageHandler(&quiet_message);
    dSetErrorHandler(&throw_ode_error);  // ODE would abort the process
    dSetDebugHandler(&throw_ode_error);
    return true;
  }();
  (void)initialized;
  thread_local const bool thread_ready = dAllocateODEDataForThread(dAllocateMaskAll) != 0;
  (void)thread_ready;
}

BodyState body_state(dBodyID body) {
  return {vec(dBodyGetPosition(body)), from_ode(dBodyGetQuaternion(body)),
          vec(dBodyGetLinearVel(body)), vec(dBodyGetAngularVel(body)), dBodyIsEnabled(body) != 0};
}

void set_body_state(dBodyID body, const BodyState& s) {
  const auto& p = s.position;
  const auto& q = s.orientation;
  set_exact_pose(body, {p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()});
  dBodySetLinearVel(body, s.linear_velocity.x(), s.linear_velocity.y(), s.linear_velocity.z());
  dBodySetAngularVel(body, s.angular_velocity.x(), s.angular_velocity.y(), s.angular_velocity.z());
  if (s.enabled) {
    dBodyEnable(body);
  } else {
    dBodyDisable(body);
  }
}

bool plausible(const BodyState& s) {
  constexpr double kMaxSpeed = 1e3;         // m/s
  constexpr double kMaxAngularSpeed = 1e4;  // rad/s
  constexpr double kMaxDistance = 1e5;      // m from the origin
  return s.position.allFinite() && s.orientation.coeffs().allFinite() &&
         s.linear_velocity.allFinite() && s.angular_velocity.allFinite() &&
         s.linear_velocity.norm() < kMaxSpeed && s.angular_velocity.norm() < kMaxAngularSpeed &&
         s.position.norm() < kMaxDistance;
}

}  // namespace detail

using detail::GeomTag;

namespace {
constexpr int kGroundGroup = -2;
constexpr int kRobotGroupBase = -100;
constexpr double kPenetrationDepth = 0.002;  // m; resting contacts sink about 1 mm
}  // namespace

/// What the parts ask of ODE, answered by the world that holds it.
struct World::Physics final : detail::WorldPhysics {
  explicit Physics(World& owner) : world(owner) {}
  void build_object(Object& object) override { world.build_object(object); }
  void destroy_object(Object& object, bool keep_body) override {
    world.destroy_ode_object(object, keep_body);
  }
  void build_joint(Joint& joint) override { world.build_joint(joint); }
  void structure_changed() override { world.structure_changed(); }
  void wake(dBodyID body) override { world.wake(body); }
  std::vector<std::string> penetrations(const Object& object) const override {
    return world.penetrations(object);
  }
  void emit(WorldEvent::Type type, const std::string& subject, const std::string& detail) override {
    world.emit(type, subject, detail);
  }
  const MaterialSpec* material(const std::string& name) const override {
    return world.spec_.material(name);
  }
  std::vector<MaterialSpec>& materials() override { return world.spec_.materials; }
  const DataRoots& data_roots() const override { return *world.files_; }
  World& world;
};

World::World(WorldSpec spec)
    : spec_(std::move(spec)),
      table_(std::make_unique<detail::ObjectTable>()),
      physics_(std::make_unique<Physics>(*this)),
      door_table_(std::make_unique<detail::DoorTable>(*table_, *physics_)),
      objects_view_(*table_),
      editor_(*table_, *door_table_, *physics_),
      doors_view_(*door_table_, *table_, *physics_) {
  bounds::check_world(spec_);  // a spec built in code keeps the same bounds as a file
  for (auto& object : spec_.objects) normalize_orientations(object);
  for (auto& robot : spec_.robots) robot.pose.orientation.normalize();
  detail::ensure_ode_ready();
  for (const auto& object : spec_.objects) table_->add(table_->take_id(), object);
  for (const auto& joint : spec_.joints) table_->add_joint(joint);
  for (const auto& door : spec_.doors) door_table_->add(door, {});
  random_seed_ = spec_.physics.seed;
  build();
  initial_ = state();
  fingerprint_ = world_fingerprint();
}

World::~World() { clear_ode(); }

void World::clear_ode() {
  if (!world_) return;
  robots_.clear();
  robot_tags_.clear();
  for (const auto& joint : table_->joints()) {
    if (joint->joint) dJointDestroy(joint->joint);
    joint->joint = nullptr;
  }
  for (const auto& object : table_->objects()) destroy_ode_object(*object);
  if (ground_) dGeomDestroy(ground_);
  ground_ = nullptr;
  dJointGroupDestroy(contact_group_);
  dSpaceDestroy(space_);
  dWorldDestroy(world_);
  dThreadingFreeImplementation(static_cast<dThreadingImplementationID>(threading_));
  world_ = nullptr;
}

namespace {
/// The space that holds the geoms, for ray casts and one-off queries (a sweep and prune: the
/// overlap check on load collides it whole). The step's pairs come from the BroadPhase.
dSpaceID create_space() { return dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ); }
}  // namespace

std::vector<dGeomID> World::collision_order() const {
  std::vector<dGeomID> order;
  if (ground_) order.push_back(ground_);
  for (const auto& object : table_->objects())
    order.insert(order.end(), object->geoms.begin(), object->geoms.end());
  for (const auto& robot : robots_) {
    for (dBodyID body : robot->bodies()) {
      for (dGeomID geom = dBodyGetFirstGeom(body); geom; geom = dBodyGetNextGeom(geom)) {
        if (dGeomGetSpace(geom) == space_) order.push_back(geom);
      }
    }
  }
  // Whatever else lies in the space (a plug-in's geom without a body), in the space's order.
  const std::unordered_set<dGeomID> listed(order.begin(), order.end());
  const int n = dSpaceGetNumGeoms(space_);
  std::vector<dGeomID> rest;
  for (int i = 0; i < n; ++i) {
    dGeomID g = dSpaceGetGeom(space_, i);
    if (!listed.count(g) && !dGeomIsSpace(g)) rest.push_back(g);
  }
  order.insert(order.end(), rest.begin(), rest.end());
  return order;
}

void World::build(const std::vector<int64_t>& body_order) {
  clear_ode();
  body_order_.clear();
  world_ = dWorldCreate();
  const auto& g = spec_.physics.gravity;
  dWorldSetGravity(world_, g.x(), g.y(), g.z());
  dWorldSetERP(world_, spec_.physics.erp);
  dWorldSetCFM(world_, spec_.physics.cfm);
  dWorldSetQuickStepNumIterations(world_, spec_.physics.solver_iterations);
  dWorldSetContactSurfaceLayer(world_, 0.001);
  // Deep penetrations (an object placed or grown into another, when allowed) are resolved
  // at a walking pace instead of an explosion.
  dWorldSetContactMaxCorrectingVel(world_, 1.0);
  // Objects at rest sleep until something touches them: a room full of objects costs little.
  // This world decides sleep (sleep_still_bodies, by ODE's rule), so that the still steps each
  // body counted are part of the state: ODE keeps its own counts to itself. A body's
  // auto-disable flag still says whether it may sleep; no samples means ODE never acts on it.
  dWorldSetAutoDisableFlag(world_, 1);
  dWorldSetAutoDisableAverageSamplesCount(world_, 0);
  // Each world gets its own threading implementation: ODE's shared default is not safe when
  // two worlds step at once (see the research notes).
  auto impl = dThreadingAllocateSelfThreadedImplementation();
  dWorldSetStepThreadingImplementation(world_, dThreadingImplementationGetFunctions(impl), impl);
  threading_ = impl;
  space_ = create_space();
  if (!broad_phase_) broad_phase_ = std::make_unique<detail::BroadPhase>();
  geoms_changed_ = true;
  contact_group_ = dJointGroupCreate(0);

  ground_ = dCreatePlane(space_, 0, 0, 1, 0);
  ground_tag_ =
      std::make_unique<GeomTag>(GeomTag{kGroundGroup, spec_.ground_friction, 0.0, 0.1, nullptr});
  dGeomSetData(ground_, ground_tag_.get());

  door_table_->wire();
  // Bodies in the order given (ODE's body list is that order reversed, and its islands follow
  // it; restore() checked it), else as loaded: objects in list order, then the robots.
  std::map<int64_t, Object*> by_id;
  for (const auto& object : table_->objects()) {
    if (object->spec.portable) {
      by_id[static_cast<int64_t>(object->id)] = object.get();
    } else {
      build_object(*object);  // no body: geoms only
    }
  }
  std::vector<int64_t> order = body_order;
  if (order.empty()) {
    for (const auto& object : table_->objects()) {
      if (object->spec.portable) order.push_back(static_cast<int64_t>(object->id));
    }
    for (std::size_t i = 0; i < spec_.robots.size(); ++i) order.push_back(robot_token(i));
  }
  // The joints once the objects' bodies are all there (before the robots, as loaded).
  const auto last_object =
      std::find_if(order.rbegin(), order.rend(), [](int64_t t) { return t >= 0; });
  if (last_object == order.rend()) {
    for (const auto& joint : table_->joints()) build_joint(*joint);
  }
  for (auto token = order.begin(); token != order.end(); ++token) {
    if (*token < 0) {
      build_robot_at(robot_of_token(*token));
      continue;
    }
    build_object(*by_id.at(*token));
    if (token == last_object.base() - 1) {
      for (const auto& joint : table_->joints()) build_joint(*joint);
    }
  }
  refresh_bodies();
}

void World::build_robot_at(std::size_t index) {
  const RobotSpec& robot = spec_.robots[index];
  const int group = kRobotGroupBase - static_cast<int>(index);
  const uint32_t seed = spec_.physics.seed + static_cast<uint32_t>(index);
  robots_.push_back(
      build_robot(robot, {world_, space_, group, seed, [this](dBodyID body) { wake(body); }}));
  body_order_.push_back(robot_token(index));
  // A plug-in knows nothing of the world's geom tags: its untagged geoms get its group. A
  // robot is driven: its bodies never fall asleep (a sleeping body ignores its motors).
  robot_tags_.push_back(std::make_unique<GeomTag>(GeomTag{group, 1.0, 0.0, 0.1, nullptr}));
  for (dBodyID body : robots_.back()->bodies()) {
    dBodySetAutoDisableFlag(body, 0);
    for (dGeomID geom = dBodyGetFirstGeom(body); geom; geom = dBodyGetNextGeom(geom)) {
      if (!dGeomGetData(geom)) dGeomSetData(geom, robot_tags_.back().get());
    }
  }
}

void World::refresh_bodies() {
  bodies_.clear();
  body_names_.clear();
  for (const auto& object : table_->objects()) {
    if (object->body) {
      bodies_.push_back(object->body);
      body_names_.push_back(object->spec.name);
    }
  }
  for (const auto& robot : robots_) {
    for (dBodyID body : robot->bodies()) {
      bodies_.push_back(body);
      body_names_.push_back(robot->name());
    }
  }
  last_good_.resize(bodies_.size());
  may_sleep_.resize(bodies_.size());
  still_steps_left_.assign(bodies_.size(), kStillStepsToSleep);
  body_index_.clear();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    last_good_[i] = detail::body_state(bodies_[i]);
    may_sleep_[i] = dBodyGetAutoDisableFlag(bodies_[i]) != 0;
    body_index_[bodies_[i]] = i;
  }
}

void World::structure_changed() {
  refresh_bodies();
  // Something appeared, vanished or moved: whatever slept on it must notice.
  for (dBodyID body : bodies_) dBodyEnable(body);
}

void World::wake(dBodyID body) {
  dBodyEnable(body);
  auto found = body_index_.find(body);
  if (found != body_index_.end()) still_steps_left_[found->second] = kStillStepsToSleep;
}

std::size_t World::sleep_still_bodies() {
  // ODE's rule (dInternalHandleAutoDisabling with one sample and no idle time), in the same
  // arithmetic: a body moving slower than both thresholds counts a still step, a faster one
  // starts again; at the count it sleeps with its velocities zeroed. A body touching nothing
  // never sleeps in mid-air. ODE wakes a sleeper that an awake body touches in its step.
  constexpr double kLinear = 0.005 * 0.005, kAngular = 0.01 * 0.01;  // (m/s)^2, (rad/s)^2
  std::size_t awake = 0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    dBodyID body = bodies_[i];
    if (!dBodyIsEnabled(body)) continue;
    ++awake;
    if (!may_sleep_[i] || dBodyGetNumJoints(body) == 0) continue;
    const dReal* v = dBodyGetLinearVel(body);
    const dReal* w = dBodyGetAngularVel(body);
    const bool still = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= kLinear &&
                       w[0] * w[0] + w[1] * w[1] + w[2] * w[2] <= kAngular;
    still_steps_left_[i] = still ? still_steps_left_[i] - 1 : kStillStepsToSleep;
    if (still_steps_left_[i] <= 0) {
      dBodyDisable(body);
      dBodySetLinearVel(body, 0, 0, 0);
      dBodySetAngularVel(body, 0, 0, 0);
      --awake;
    }
  }
  return awake;
}

void World::build_object(Object& o) {
  geoms_changed_ = true;
  const ObjectSpec& s = o.spec;
  const MaterialSpec* material = spec_.material(s.material);
  if (!material) material = &spec_.materials.front();
  // Collision group: an object, or a whole door-switch structure, never collides with itself.
  const int group = o.door >= 0 ? 1'000'000 + o.door : static_cast<int>(o.id);
  o.tag = GeomTag{group, material->friction, material->bounce, material->bounce_velocity, &o.spec};

  // Mass of the components, each rotated and moved into the object's frame (ODE applies the
  // parallel axis theorem), then about the combined centre of mass.
  dMass total;
  dMassSetZero(&total);
  for (const auto& c : s.components) {
    dMass m;
    switch (c.shape) {
      case Shape::Box:
        dMassSetBox(&m, s.density, c.size.x(), c.size.y(), c.size.z());
        break;
      case Shape::Cylinder:
        dMassSetCylinder(&m, s.density, 3, c.size.x(), c.size.z());
        break;
      case Shape::Sphere:
        dMassSetSphere(&m, s.density, c.size.x());
        break;
    }
    dMatrix3 r;
    dQuaternion q;
    detail::to_ode(c.pose.orientation, q);
    dQtoR(q, r);
    dMassRotate(&m, r);
    dMassTranslate(&m, c.pose.position.x(), c.pose.position.y(), c.pose.position.z());
    dMassAdd(&total, &m);
  }
  o.com = {total.c[0], total.c[1], total.c[2]};

  for (const auto& c : s.components) {
    dGeomID geom = nullptr;
    switch (c.shape) {
      case Shape::Box:
        geom = dCreateBox(space_, c.size.x(), c.size.y(), c.size.z());
        break;
      case Shape::Cylinder:
        geom = dCreateCylinder(space_, c.size.x(), c.size.z());
        break;
      case Shape::Sphere:
        geom = dCreateSphere(space_, c.size.x());
        break;
    }
    dGeomSetData(geom, &o.tag);
    o.geoms.push_back(geom);
  }

  if (s.portable) {
    if (o.body) {  // kept: the same place in ODE's order, as if made anew
      dBodySetDynamic(o.body);
      dBodySetForce(o.body, 0, 0, 0);
      dBodySetTorque(o.body, 0, 0, 0);
    } else {
      o.body = dBodyCreate(world_);
      body_order_.push_back(static_cast<int64_t>(o.id));
    }
    dMassTranslate(&total, -o.com.x(), -o.com.y(), -o.com.z());
    dBodySetMass(o.body, &total);
    detail::set_body_pose(o.body, s.pose * Pose{o.com, Eigen::Quaterniond::Identity()});
    for (std::size_t i = 0; i < s.components.size(); ++i) {
      const auto& c = s.components[i];
      dGeomSetBody(o.geoms[i], o.body);
      const Eigen::Vector3d offset = c.pose.position - o.com;
      dGeomSetOffsetPosition(o.geoms[i], offset.x(), offset.y(), offset.z());
      dQuaternion q;
      detail::to_ode(c.pose.orientation, q);
      dGeomSetOffsetQuaternion(o.geoms[i], q);
    }
    if (s.frozen) dBodySetKinematic(o.body);
  } else {
    for (std::size_t i = 0; i < s.components.size(); ++i) {
      const Pose p = s.pose * s.components[i].pose;
      dGeomSetPosition(o.geoms[i], p.position.x(), p.position.y(), p.position.z());
      dQuaternion q;
      detail::to_ode(p.orientation, q);
      dGeomSetQuaternion(o.geoms[i], q);
    }
  }
}

void World::destroy_ode_object(Object& o, bool keep_body) {
  geoms_changed_ = true;
  for (auto& robot : robots_) {
    if (o.body) robot->forget_body(o.body);
  }
  for (dGeomID g : o.geoms) dGeomDestroy(g);
  o.geoms.clear();
  if (o.body && keep_body) return;
  if (o.body) {
    dBodyDestroy(o.body);
    const auto token = static_cast<int64_t>(o.id);
    body_order_.erase(std::find(body_order_.begin(), body_order_.end(), token));
  }
  o.body = nullptr;
}

void World::set_data_roots(std::shared_ptr<const DataRoots> roots) {
  files_ = roots ? std::move(roots) : DataRoots::anywhere();
}

void World::build_joint(Joint& j) {
  if (j.joint) {
    j.position = j.spec.type == JointSpec::Type::Slider ? dJointGetSliderPosition(j.joint)
                                                        : dJointGetHingeAngle(j.joint);
    dJointDestroy(j.joint);
    j.joint = nullptr;
  }
  Object* moving = table_->find_named(j.spec.body1);
  if (!moving) return;
  dBodyID other = nullptr;
  if (!j.spec.body2.empty()) {
    if (const Object* second = table_->find_named(j.spec.body2)) other = second->body;
  }
  geoms_changed_ = true;  // the body is put elsewhere and back, maybe asleep
  // ODE takes a joint's zero where the bodies are when it is attached: move the moving body
  // back by the joint's position, attach, and put it where it was.
  const BodyState now = detail::body_state(moving->body);
  BodyState zero = now;
  const Eigen::Vector3d axis = j.spec.axis;
  if (j.spec.type == JointSpec::Type::Slider) {
    zero.position -= axis * j.position;
    j.joint = dJointCreateSlider(world_, nullptr);
  } else {
    const Eigen::Quaterniond back(Eigen::AngleAxisd(-j.position, axis));
    zero.position = j.spec.anchor + back * (now.position - j.spec.anchor);
    zero.orientation = back * now.orientation;
    j.joint = dJointCreateHinge(world_, nullptr);
  }
  detail::set_body_state(moving->body, zero);
  dBodySetAutoDisableFlag(moving->body, 0);  // a mechanism must answer its motor at any time
  dJointAttach(j.joint, moving->body, other);
  if (j.spec.type == JointSpec::Type::Slider) {
    dJointSetSliderAxis(j.joint, axis.x(), axis.y(), axis.z());
    dJointSetSliderParam(j.joint, dParamLoStop, j.spec.lo);
    dJointSetSliderParam(j.joint, dParamHiStop, j.spec.hi);
    dJointSetSliderParam(j.joint, dParamFMax, j.spec.max_force);
    dJointSetSliderParam(j.joint, dParamVel, j.spec.velocity);
  } else {
    dJointSetHingeAnchor(j.joint, j.spec.anchor.x(), j.spec.anchor.y(), j.spec.anchor.z());
    dJointSetHingeAxis(j.joint, axis.x(), axis.y(), axis.z());
    dJointSetHingeParam(j.joint, dParamLoStop, j.spec.lo);
    dJointSetHingeParam(j.joint, dParamHiStop, j.spec.hi);
    dJointSetHingeParam(j.joint, dParamFMax, j.spec.max_force);
    dJointSetHingeParam(j.joint, dParamVel, j.spec.velocity);
  }
  detail::set_body_state(moving->body, now);
}

RobotModel* World::robot(const std::string& name) {
  for (auto& r : robots_) {
    if (r->name() == name) return r.get();
  }
  return nullptr;
}

void World::near_callback(void* data, dGeomID a, dGeomID b) {
  auto* self = static_cast<World*>(data);
  const auto* ta = static_cast<const GeomTag*>(dGeomGetData(a));
  const auto* tb = static_cast<const GeomTag*>(dGeomGetData(b));
  if (ta->group == tb->group) return;
  dBodyID ba = dGeomGetBody(a);
  dBodyID bb = dGeomGetBody(b);
  if (!ba && !bb) return;  // two static geoms
  // Nothing asleep moves: no contacts between sleeping bodies and the static world (ODE wakes a
  // sleeper when an awake body touches it, and its other contacts come back the next step).
  // Without this a floor of resting objects costs one contact joint per corner every step.
  if ((!ba || !dBodyIsEnabled(ba)) && (!bb || !dBodyIsEnabled(bb))) return;
  if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;

  dContact contacts[detail::kMaxContacts];
  const int n = dCollide(a, b, detail::kMaxContacts, &contacts[0].geom, sizeof(dContact));
  if (n == 0) return;
  const double mu = std::sqrt(ta->friction * tb->friction);
  const double bounce = std::max(ta->bounce, tb->bounce);
  const double bounce_velocity = std::max(ta->bounce_velocity, tb->bounce_velocity);
  for (int i = 0; i < n; ++i) {
    dSurfaceParameters& s = contacts[i].surface;
    s.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
    s.mu = mu;
    s.soft_erp = 0.2;
    s.soft_cfm = 1e-5;
    if (bounce > 0) {
      s.mode |= dContactBounce;
      s.bounce = bounce;
      s.bounce_vel = bounce_velocity;
    }
    dJointID joint = dJointCreateContact(self->world_, self->contact_group_, &contacts[i]);
    dJointAttach(joint, ba, bb);
  }
  self->contacts_ += n;
}

double detail::point_depth(dGeomID g, const dReal* p) {
  switch (dGeomGetClass(g)) {
    case dBoxClass:
      return dGeomBoxPointDepth(g, p[0], p[1], p[2]);
    case dSphereClass:
      return dGeomSpherePointDepth(g, p[0], p[1], p[2]);
    case dPlaneClass:
      return dGeomPlanePointDepth(g, p[0], p[1], p[2]);
    case dCylinderClass: {
      dReal radius, length;
      dGeomCylinderGetParams(g, &radius, &length);
      dVector3 local;
      dGeomGetPosRelPoint(g, p[0], p[1], p[2], local);
      const double radial = radius - std::hypot(local[0], local[1]);
      const double axial = length / 2 - std::fabs(local[2]);
      return std::min(radial, axial);
    }
    default:
      return -1.0;
  }
}

namespace {

struct PenetrationQuery {
  const detail::GeomTag* tag;
  dBodyID body;
  std::vector<const detail::GeomTag*> hits;
};

void penetration_callback(void* data, dGeomID a, dGeomID b) {
  auto* q = static_cast<PenetrationQuery*>(data);
  const auto* ta = static_cast<const GeomTag*>(dGeomGetData(a));
  const auto* tb = static_cast<const GeomTag*>(dGeomGetData(b));
  if (ta->group == tb->group) return;
  dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
  if (!ba && !bb) return;  // fixed against fixed (or the ground): no physical meaning
  if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;
  dContactGeom contacts[detail::kMaxContacts];
  const int n = dCollide(a, b, detail::kMaxContacts, contacts, sizeof(dContactGeom));
  auto centre_inside = [](dGeomID outer, dGeomID inner) {
    return dGeomGetClass(inner) != dPlaneClass &&
           detail::point_depth(outer, dGeomGetPosition(inner)) > kPenetrationDepth;
  };
  bool deep = centre_inside(a, b) || centre_inside(b, a);
  for (int i = 0; i < n && !deep; ++i) deep = contacts[i].depth > kPenetrationDepth;
  if (deep) q->hits.push_back(ta == q->tag ? tb : ta);
}

}  // namespace

std::vector<std::string> World::penetrations(const Object& object) const {
  PenetrationQuery query{&object.tag, object.body, {}};
  for (dGeomID g : object.geoms) {
    dSpaceCollide2(g, reinterpret_cast<dGeomID>(space_), &query, &penetration_callback);
  }
  std::vector<std::string> names;
  auto add = [&names](const std::string& name) {
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  };
  for (const auto* hit : query.hits) {
    if (hit == ground_tag_.get()) {
      add("ground");
      continue;
    }
    bool found = false;
    for (const auto& o : table_->objects()) {
      if (&o->tag == hit) {
        add(o->spec.name);
        found = true;
      }
    }
    if (!found) {
      for (const auto& r : robots_) add(r->name());  // robot geoms carry their own tags
    }
  }
  return names;
}

std::vector<ShapeView> World::shapes() const {
  std::vector<ShapeView> out;
  for (const auto& o : table_->objects()) {
    for (std::size_t i = 0; i < o->geoms.size(); ++i) {
      const ComponentSpec& c = o->spec.components[i];
      dQuaternion q;
      dGeomGetQuaternion(o->geoms[i], q);
      out.push_back({c.shape,
                     c.size,
                     {detail::vec(dGeomGetPosition(o->geoms[i])), detail::from_ode(q)},
                     c.color,
                     c.texture});
    }
  }
  for (const auto& r : robots_) {
    auto parts = r->shapes();
    out.insert(out.end(), parts.begin(), parts.end());
  }
  return out;
}

void World::emit(WorldEvent::Type type, const std::string& subject, const std::string& detail) {
  events_.push_back({type, time(), subject, detail});
}

std::vector<WorldEvent> World::take_events() {
  std::vector<WorldEvent> out;
  out.swap(events_);
  return out;
}

bool World::check_stability() {
  bool stable = true;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (!dBodyIsEnabled(bodies_[i])) continue;  // asleep: it did not move, last_good_ holds
    BodyState now = detail::body_state(bodies_[i]);
    if (detail::plausible(now)) {
      last_good_[i] = now;
      continue;
    }
    // Put the body back where it last was, at rest, so nothing spreads; report it.
    BodyState back = last_good_[i];
    back.linear_velocity.setZero();
    back.angular_velocity.setZero();
    detail::set_body_state(bodies_[i], back);
    still_steps_left_[i] = kStillStepsToSleep;  // woken
    emit(WorldEvent::Type::Instability, body_names_[i],
         "a body went unstable (non-finite or implausible state); put back at rest");
    stable = false;
  }
  return stable;
}

void World::keep_robot_commands(const std::string& robots) {
  for (auto& robot : robots_) {
    const std::string& name = robot->name();
    bool held = robots.empty();
    for (std::size_t at = robots.find(name); !held && at != std::string::npos;
         at = robots.find(name, at + 1)) {
      const std::size_t end = at + name.size();
      held = (at == 0 || robots[at - 1] == ',') && (end == robots.size() || robots[end] == ',');
    }
    if (held) robot->keep_command(time());
  }
}

bool World::step() {
  using Clock = std::chrono::steady_clock;
  detail::ensure_ode_ready();
  if (!fault_.empty()) return false;
  const auto begin = Clock::now();
  const double now = time();
  door_table_->before_step();
  const auto doors_updated = Clock::now();
  for (auto& robot : robots_) robot->before_step(now);
  contacts_ = 0;
  bool anything_awake = true;
  auto collided = begin, solved = begin;
  const auto robots_ready = Clock::now();
  try {
    if (geoms_changed_) {
      broad_phase_->track(collision_order());
      geoms_changed_ = false;
    }
    dSpaceClean(space_);
    broad_phase_->collide(this, &World::near_callback);
    collided = Clock::now();
    // QuickStep reorders constraints with ODE's one global random generator: give it this
    // world's own state, so worlds in one process never disturb each other's runs.
    dRandSetSeed(random_seed_);
    // Nothing awake: nothing moves, and ODE's step (which walks every body) would change
    // nothing, not even its random state. A world asleep costs the walk above alone.
    anything_awake = sleep_still_bodies() > 0;
    if (anything_awake) dWorldQuickStep(world_, spec_.physics.step);
    solved = Clock::now();
  } catch (const detail::OdeError& e) {
    // Inside a step ODE's own state may be left half-changed: this world steps no more.
    fault_ = e.what();
    emit(WorldEvent::Type::Instability, spec_.name,
         std::string(e.what()) + "; this world steps no more (load a world)");
    return false;
  }
  random_seed_ = dRandGetSeed();
  dJointGroupEmpty(contact_group_);
  ++steps_;
  const bool stable = !anything_awake || check_stability();
  const auto checked = Clock::now();
  for (auto& robot : robots_) {
    robot->after_step(time(), spec_.physics.step);
    for (auto& event : robot->take_events()) events_.push_back(std::move(event));
  }
  const auto sensed = Clock::now();
  door_table_->after_step();
  const auto end = Clock::now();
  auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
  ++profile_.steps;
  profile_.robots += seconds(robots_ready - doors_updated) + seconds(sensed - checked);
  profile_.collision += seconds(collided - robots_ready);
  profile_.solver += seconds(solved - collided);
  profile_.other +=
      seconds(doors_updated - begin) + seconds(checked - solved) + seconds(end - sensed);
  return stable;
}

}  // namespace macsim
