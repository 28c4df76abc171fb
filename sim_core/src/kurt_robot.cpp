#include "macsim/sim_core/kurt_robot.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "drive_command.h"
#include "ode_support.h"
#include "ray_caster.h"
#include "robot_readings.h"
#include "state_archive.h"

namespace macsim {

using detail::add_stereo_frames;
using detail::body_pose;
using detail::GeomTag;
using detail::ground_truth_reading;
using detail::make_robot_body;
using detail::odometry_reading;
using detail::robot_mount;
using detail::scan_reading;
using detail::set_body_pose;
using detail::wrap_angle;

namespace {

constexpr int kLeftMiddle = 1;
constexpr int kRightMiddle = 4;
constexpr double kMagnetHeight = robot::kurt3d::kMagnetHeight;
constexpr double kRotunitTicks = robot::kurt3d::kRotunitTicks;

double wrap_difference(double a, double b) { return std::remainder(a - b, 2.0 * M_PI); }

double yaw_of(const Eigen::Quaterniond& q) {
  const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

/// A position motor: velocity towards the target, limited in speed.
double servo_velocity(double target, double position, double max_speed) {
  return std::clamp(5.0 * (target - position), -max_speed, max_speed);
}

/// A standard normal number. A fresh distribution each time keeps no cached value, so the
/// generator alone is the noise's state.
double gaussian(std::mt19937& rng) { return std::normal_distribution<double>(0.0, 1.0)(rng); }

/// A robot's state as built: encoders and odometry from the drive parameters, seeded noise.
KurtRobot::State initial_state(const KurtConfig& config) {
  KurtRobot::State s;
  s.encoders = {EncoderCounter(config.drive.ticks_per_turn),
                EncoderCounter(config.drive.ticks_per_turn)};
  s.odometry = KurtOdometry(config.drive);
  s.noise_rng.seed(config.noise_seed);
  s.next_frame_time = config.drive.frame_period;
  return s;
}

}  // namespace

Eigen::Vector3d laser_origin(LaserMount mount) {
  return Eigen::Vector3d(mount == LaserMount::Rotating ? robot::kurt3d::kRotatingLaser.data()
                                                       : robot::kurt3d::kFixedLaser.data());
}

StereoMount kurt3d_cameras() {
  namespace k = robot::kurt3d;
  const Eigen::Quaterniond pitch(Eigen::AngleAxisd(k::kCameraPitch, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d left(k::kLeftCamera.data());
  return {{left, pitch}, {{left.x(), -left.y(), left.z()}, pitch}};
}

namespace {
/// The configuration as built into a world: noise seeded by the build, frames at the spec's rate.
KurtConfig as_built(KurtConfig config, const RobotSpec& spec, const RobotBuild& build) {
  config.noise_seed = build.noise_seed;
  config.drive.frame_period = 1.0 / spec.encoder_rate;
  return config;
}
}  // namespace

KurtRobot::KurtRobot(const RobotSpec& spec, const RobotBuild& build, const KurtConfig& config)
    : RobotModel(spec),
      config_(as_built(config, spec, build)),
      world_(build.world),
      wake_(build.wake),
      space_(build.space),
      chassis_tag_(
          std::make_unique<GeomTag>(GeomTag{build.collision_group, 0.5, 0.0, 0.1, nullptr})),
      wheel_tag_(std::make_unique<GeomTag>(
          GeomTag{build.collision_group, config.body.wheel_friction, 0.0, 0.1, nullptr})),
      crane_tag_(std::make_unique<GeomTag>(GeomTag{build.collision_group, 0.8, 0.0, 0.1, nullptr})),
      rays_(std::make_unique<detail::RayCaster>(build.space, build.collision_group)),
      state_{initial_state(config_)} {
  dWorldID world = build.world;
  dSpaceID space = build.space;
  detail::ensure_ode_ready();
  const KurtBodyParams& body = config_.body;
  const double r = config_.drive.wheel_radius();
  const Eigen::Quaterniond q = spec.pose.orientation;
  const Eigen::Vector3d base_link =
      spec.pose.position + q * Eigen::Vector3d(0, 0, body.wheel_axle_below_base_link + r);

  // Chassis: one body at the centre of mass, the collision box centred on base_link.
  dMass mass;
  dMassSetParameters(&mass, body.base_mass, 0, 0, 0, body.base_inertia.x(), body.base_inertia.y(),
                     body.base_inertia.z(), 0, 0, 0);
  chassis_ = make_robot_body(
      world, {base_link + q * Eigen::Vector3d(0, 0, -body.com_below_base_link), q}, mass);
  dGeomID box = dCreateBox(space, body.base_size.x(), body.base_size.y(), body.base_size.z());
  dGeomSetBody(box, chassis_);
  dGeomSetOffsetPosition(box, 0, 0, body.com_below_base_link);
  dGeomSetData(box, chassis_tag_.get());
  geoms_.push_back(box);

  // Wheels: cylinders (ODE's axis is local z, turned onto the robot's y) on hinge motors.
  const Eigen::Quaterniond wheel_q =
      q * Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitY();
  const double xs[3] = {body.wheel_x, 0.0, -body.wheel_x};
  for (int i = 0; i < 6; ++i) {
    const double y = i < 3 ? body.wheel_y : -body.wheel_y;
    const Eigen::Vector3d centre =
        base_link + q * Eigen::Vector3d(xs[i % 3], y, -body.wheel_axle_below_base_link);
    dMass wheel_mass;
    dMassSetCylinderTotal(&wheel_mass, body.wheel_mass, 3, r, body.wheel_width);
    dBodyID wheel = make_robot_body(world, {centre, wheel_q}, wheel_mass);
    dGeomID geom = dCreateCylinder(space, r, body.wheel_width);
    dGeomSetBody(geom, wheel);
    dGeomSetData(geom, wheel_tag_.get());
    // Attached (wheel, chassis): the motor's velocity is the wheel's rate about +y relative
    // to the chassis, so a positive rate rolls the robot forwards.
    dJointID hinge = dJointCreateHinge(world, nullptr);
    dJointAttach(hinge, wheel, chassis_);
    dJointSetHingeAnchor(hinge, centre.x(), centre.y(), centre.z());
    dJointSetHingeAxis(hinge, axis.x(), axis.y(), axis.z());
    dJointSetHingeParam(hinge, dParamFMax, body.wheel_torque);
    dJointSetHingeParam(hinge, dParamVel, 0.0);
    wheels_[i] = wheel;
    hinges_[i] = hinge;
    geoms_.push_back(geom);
  }
  if (config_.crane) build_crane(world, space, {base_link, q});
  for (std::size_t i = 0; i < state_.ranges.size(); ++i)
    state_.ranges[i] = {&kurt_range_sensors()[i], kInvalidRange};
  state_.start_yaw = state_.last_yaw = state_.yaw_unwrapped = yaw_of(q);
  command_rotunit(config_.rotunit_speed);
  state_.next_scan_time = 1.0 / config_.laser_rate;
}

void KurtRobot::build_crane(dWorldID world, dSpaceID space, const Pose& base_link) {
  const CraneParams& c = config_.crane_params;
  const Eigen::Quaterniond q = base_link.orientation;
  const double box_top = config_.body.base_size.z() / 2;
  auto at = [&](double x, double y, double z) -> Eigen::Vector3d {
    return base_link.position + q * Eigen::Vector3d(x, y, z);
  };
  auto add_geom = [&](dGeomID g, dBodyID b) {
    dGeomSetBody(g, b);
    dGeomSetData(g, crane_tag_.get());
    geoms_.push_back(g);
  };

  // Turret on the chassis roof, slewing about the vertical.
  const double turret_height = c.pivot_height - box_top;
  dMass m;
  dMassSetCylinderTotal(&m, 1.0, 3, 0.05, turret_height);
  turret_ = make_robot_body(world, {at(c.pivot_x, 0, box_top + turret_height / 2), q}, m);
  add_geom(dCreateCylinder(space, 0.05, turret_height), turret_);
  slew_ = dJointCreateHinge(world, nullptr);
  dJointAttach(slew_, turret_, chassis_);
  const Eigen::Vector3d slew_anchor = at(c.pivot_x, 0, box_top);
  const Eigen::Vector3d up = q * Eigen::Vector3d::UnitZ();
  dJointSetHingeAnchor(slew_, slew_anchor.x(), slew_anchor.y(), slew_anchor.z());
  dJointSetHingeAxis(slew_, up.x(), up.y(), up.z());

  // Boom from the pivot forwards; lifting turns it about -y (the tip goes up).
  dMassSetBoxTotal(&m, 0.5, c.boom_length, 0.04, 0.04);
  boom_ = make_robot_body(world, {at(c.pivot_x + c.boom_length / 2, 0, c.pivot_height), q}, m);
  add_geom(dCreateBox(space, c.boom_length, 0.04, 0.04), boom_);
  lift_ = dJointCreateHinge(world, nullptr);
  dJointAttach(lift_, boom_, turret_);
  const Eigen::Vector3d pivot = at(c.pivot_x, 0, c.pivot_height);
  const Eigen::Vector3d lift_axis = q * -Eigen::Vector3d::UnitY();
  dJointSetHingeAnchor(lift_, pivot.x(), pivot.y(), pivot.z());
  dJointSetHingeAxis(lift_, lift_axis.x(), lift_axis.y(), lift_axis.z());
  dJointSetHingeParam(lift_, dParamLoStop, robot::kurt3d::kLiftMin);
  dJointSetHingeParam(lift_, dParamHiStop, robot::kurt3d::kLiftMax);

  // The magnet hangs below the boom tip on the hoist (a slider along the boom's down axis).
  dMassSetCylinderTotal(&m, c.magnet_mass, 3, c.magnet_radius, kMagnetHeight);
  magnet_ = make_robot_body(
      world, {at(c.pivot_x + c.boom_length, 0, c.pivot_height - 0.02 - kMagnetHeight / 2), q}, m);
  add_geom(dCreateCylinder(space, c.magnet_radius, kMagnetHeight), magnet_);
  hoist_ = dJointCreateSlider(world, nullptr);
  dJointAttach(hoist_, magnet_, boom_);
  const Eigen::Vector3d down = q * -Eigen::Vector3d::UnitZ();
  dJointSetSliderAxis(hoist_, down.x(), down.y(), down.z());
  dJointSetSliderParam(hoist_, dParamLoStop, 0.0);
  dJointSetSliderParam(hoist_, dParamHiStop, c.max_hoist);

  capture_ = dCreateCylinder(nullptr, c.magnet_radius + c.capture_distance,
                             kMagnetHeight + 2 * c.capture_distance);
  hold_feedback_ = std::make_unique<dJointFeedback>();
}

KurtRobot::~KurtRobot() {
  if (hold_) dJointDestroy(hold_);
  for (dJointID h : hinges_) dJointDestroy(h);
  for (dJointID j : {slew_, lift_, hoist_}) {
    if (j) dJointDestroy(j);
  }
  for (dGeomID g : geoms_) dGeomDestroy(g);
  if (capture_) dGeomDestroy(capture_);
  for (dBodyID b : bodies()) dBodyDestroy(b);
}

std::vector<dBodyID> KurtRobot::bodies() const {
  std::vector<dBodyID> all{chassis_};
  all.insert(all.end(), wheels_.begin(), wheels_.end());
  for (dBodyID b : {turret_, boom_, magnet_}) {
    if (b) all.push_back(b);
  }
  return all;
}

// ---- commands ----------------------------------------------------------------------------

bool KurtRobot::execute(const robot::RobotCommand& command, double now) {
  if (detail::execute_drive(*this, command, now)) return true;
  if (const auto* r = command.as<robot::RotunitSpeed>()) {
    return config_.laser == LaserMount::Rotating && command_rotunit(r->speed);
  }
  if (const auto* c = command.as<robot::CraneTarget>()) {
    return config_.crane && command_crane({c->slew, c->lift, c->hoist});
  }
  if (const auto* m = command.as<robot::MagnetSwitch>()) {
    return config_.crane && command_magnet(m->on);
  }
  return false;
}

void KurtRobot::command_twist(double linear, double angular, double now) {
  command_wheel_speeds(wheel_speeds_from_twist(linear, angular, config_.drive), now);
}

void KurtRobot::command_wheel_speeds(WheelSpeeds speeds, double now) {
  state_.commanded = quantize_to_speed_cm(speeds);
  state_.last_command_time = now;
}

bool KurtRobot::command_crane(const CraneCommand& target) {
  const CraneParams& c = config_.crane_params;
  state_.crane.slew = std::clamp(target.slew, -M_PI, M_PI);
  state_.crane.lift = std::clamp(target.lift, robot::kurt3d::kLiftMin, robot::kurt3d::kLiftMax);
  state_.crane.hoist = std::clamp(target.hoist, 0.0, c.max_hoist);
  return config_.crane;
}

bool KurtRobot::command_magnet(bool on) {
  state_.magnet_on = on;
  if (!on && hold_) release("magnet switched off");
  return config_.crane;
}

bool KurtRobot::command_rotunit(double speed) {
  state_.rotunit_speed = rotunit_speed_from_command(rotunit_speed_command(speed));
  return config_.laser == LaserMount::Rotating;
}

void KurtRobot::keep_command(double now) {
  if (now - state_.last_command_time < config_.drive.command_timeout) {
    state_.last_command_time = now;
  }
}

// ---- stepping ----------------------------------------------------------------------------

void KurtRobot::before_step(double now) {
  const bool fresh = now - state_.last_command_time < config_.drive.command_timeout;
  state_.active = fresh ? state_.commanded : WheelSpeeds{};
  const double r = config_.drive.wheel_radius();
  for (int i = 0; i < 6; ++i) {
    const double rim_speed = i < 3 ? state_.active.left : state_.active.right;
    dJointSetHingeParam(hinges_[i], dParamVel, rim_speed / r);
  }
  if (!config_.crane) return;
  const CraneParams& c = config_.crane_params;
  dJointSetHingeParam(slew_, dParamFMax, c.slew_torque);
  dJointSetHingeParam(slew_, dParamVel,
                      servo_velocity(state_.crane.slew, dJointGetHingeAngle(slew_), c.slew_speed));
  dJointSetHingeParam(lift_, dParamFMax, c.lift_torque);
  dJointSetHingeParam(lift_, dParamVel,
                      servo_velocity(state_.crane.lift, dJointGetHingeAngle(lift_), c.lift_speed));
  dJointSetSliderParam(hoist_, dParamFMax, c.hoist_force);
  dJointSetSliderParam(
      hoist_, dParamVel,
      servo_velocity(state_.crane.hoist, dJointGetSliderPosition(hoist_), c.hoist_speed));
}

void KurtRobot::update_wheel_angles() {
  const int middles[2] = {kLeftMiddle, kRightMiddle};
  for (int side = 0; side < 2; ++side) {
    const double angle = dJointGetHingeAngle(hinges_[middles[side]]);
    state_.encoder_angle[side] += wrap_difference(angle, state_.last_hinge_angle[side]);
    state_.last_hinge_angle[side] = angle;
  }
}

void KurtRobot::after_step(double now, double step) {
  now_ = now;
  update_wheel_angles();
  const double yaw = yaw_of(base_link_pose().orientation);
  state_.yaw_unwrapped += wrap_difference(yaw, state_.last_yaw);
  state_.last_yaw = yaw;
  if (config_.crane) run_magnet();
  if (config_.laser == LaserMount::Rotating) {
    // The unit turns at its commanded speed (its own controller holds it).
    state_.rotunit_angle += state_.rotunit_speed * step;
  }
  if (config_.laser != LaserMount::None && now + 1e-9 >= state_.next_scan_time) {
    state_.next_scan_time += 1.0 / config_.laser_rate;
    sweep_laser(now);
  }
  if (now + 1e-9 < state_.next_frame_time) return;
  state_.next_frame_time += config_.drive.frame_period;
  const int left = state_.encoders[0].ticks_since_last(state_.encoder_angle[0]);
  const int right = state_.encoders[1].ticks_since_last(state_.encoder_angle[1]);
  state_.odometry.integrate_frame(left, right);
  read_frame_sensors(now);
  ++state_.frames;
}

void KurtRobot::read_frame_sensors(double now) {
  const Pose base = base_link_pose();
  if (config_.range_sensors) {
    // Three rays across each cone, all cast as one bundle: the nearest echo of a cone wins, as
    // the real sensors report.
    std::vector<detail::RayCaster::Ray> rays;
    rays.reserve(3 * state_.ranges.size());
    for (std::size_t i = 0; i < state_.ranges.size(); ++i) {
      const RangeSensorSpec& s = kurt_range_sensors()[i];
      const Eigen::Vector3d origin =
          base.position + base.orientation * Eigen::Vector3d(s.x, s.y, 0);
      for (double offset : {-s.field_of_view / 2, 0.0, s.field_of_view / 2}) {
        const Eigen::Vector3d dir = base.orientation * Eigen::Vector3d(std::cos(s.yaw + offset),
                                                                       std::sin(s.yaw + offset), 0);
        rays.push_back({origin, dir, s.max_range + 0.05});
      }
    }
    const auto hits = rays_->cast_bundle(rays);
    for (std::size_t i = 0; i < state_.ranges.size(); ++i) {
      const RangeSensorSpec& s = kurt_range_sensors()[i];
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t k = 3 * i; k < 3 * i + 3; ++k) {
        if (hits[k]) nearest = std::min(nearest, *hits[k]);
      }
      // The sensor gives an ADC value and the driver converts it back (whole centimetres,
      // invalid outside its raw window), so readings carry the real robot's quirks: IR valid
      // from 0.10 only up to 0.53 m, ultrasound only from 0.23 m.
      const bool echo = nearest >= s.min_range && nearest <= s.max_range;
      const int raw = !echo     ? 0
                      : s.sonar ? sonar_raw_from_range(nearest)
                                : ir_raw_from_range(nearest);
      state_.ranges[i] = {&s, s.sonar ? sonar_range_from_raw(raw) : ir_range_from_raw(raw)};
    }
  }
  double noise = 0.0;
  if (config_.gyro_noise > 0) noise = config_.gyro_noise * gaussian(state_.noise_rng);
  const Eigen::Vector3d x = base.orientation * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d y = base.orientation * Eigen::Vector3d::UnitY();
  state_.imu.yaw =
      wrap_angle(state_.yaw_unwrapped - state_.start_yaw + config_.gyro_drift * now + noise);
  state_.imu.yaw_rate = angular_velocity().z();
  state_.imu.pitch = -std::asin(std::clamp(x.z(), -1.0, 1.0));
  state_.imu.roll = std::asin(std::clamp(y.z(), -1.0, 1.0));
  state_.imu.yaw_variance = config_.gyro_noise * config_.gyro_noise;
}

void KurtRobot::sweep_laser(double now) {
  const Pose base = base_link_pose();
  const bool rotating = config_.laser == LaserMount::Rotating;
  const bool turning = rotating && state_.rotunit_speed != 0.0;
  // KURT360: the LMS200 on the rotating unit behind the crane, 0.35 m above base_link;
  // KURT2: fixed at the front, 0.11 m above base_link (kurt_driver's URDFs).
  state_.scan.origin = laser_origin(config_.laser);
  state_.scan.stamp = now;
  state_.scan.angle_min = -M_PI / 2;
  state_.scan.angle_increment = M_PI / 180;
  state_.scan.rotunit_angle = rotunit_angle();
  state_.scan.ranges.assign(181, std::numeric_limits<float>::infinity());
  const Eigen::Vector3d origin = base.position + base.orientation * state_.scan.origin;
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(state_.scan.rotunit_angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  // The beams' angles never change: their cosines and sines once, the same values every sweep.
  static const std::array<std::pair<double, double>, 181> beam = [] {
    std::array<std::pair<double, double>, 181> table;
    for (int i = 0; i < 181; ++i) {
      const double a = -M_PI / 2 + i * (M_PI / 180);
      table[i] = {std::cos(a), std::sin(a)};
    }
    return table;
  }();
  std::array<Eigen::Vector3d, 181> local;
  std::vector<Eigen::Vector3d> directions(181);
  const Eigen::Matrix3d to_world = base.orientation.toRotationMatrix();
  for (int i = 0; i < 181; ++i) {
    const auto [c, s] = beam[i];
    local[i] =
        rotating ? Eigen::Vector3d(turn * Eigen::Vector3d(c, 0, s)) : Eigen::Vector3d(c, s, 0);
    directions[i] = to_world * local[i];
  }
  // One sweep, one fan: what lies off the scan plane is set aside once for all 181 rays.
  const auto hits = rays_->cast_fan(origin, directions, state_.scan.range_max);
  detail::SweepNoise noise(state_.noise_rng, config_.laser_noise);
  for (int i = 0; i < 181; ++i) {
    const auto& hit = hits[i];
    if (!hit || *hit < state_.scan.range_min) continue;
    const double range = *hit + noise();
    state_.scan.ranges[i] = static_cast<float>(range);
    if (turning) {
      if (state_.cloud_in_progress.points.empty()) {
        // Room for a whole revolution at once: a cloud grown point by point was copied and
        // mapped anew at every doubling.
        const double sweeps = 2 * M_PI / std::fabs(state_.rotunit_speed) * config_.laser_rate;
        state_.cloud_in_progress.points.reserve(
            static_cast<std::size_t>(std::min(sweeps + 1.0, 2000.0)) * 181);
      }
      state_.cloud_in_progress.points.push_back(
          (state_.scan.origin + local[i] * range).cast<float>());
    }
  }
  ++state_.scans;
  if (rotating && !turning) {  // a cloud is one revolution: none is assembled while it stands
    state_.cloud_in_progress = PointCloud{};
    state_.cloud_start_angle = state_.rotunit_angle;
  }
  if (rotating && std::fabs(state_.rotunit_angle - state_.cloud_start_angle) >= 2 * M_PI) {
    state_.cloud_in_progress.stamp = now;
    state_.cloud = std::move(state_.cloud_in_progress);
    state_.cloud_in_progress = PointCloud{};
    state_.cloud_start_angle = state_.rotunit_angle;
    ++state_.clouds;
  }
}

double KurtRobot::rotunit_angle() const {
  const double turn = std::fmod(state_.rotunit_angle, 2 * M_PI);
  const double positive = turn < 0 ? turn + 2 * M_PI : turn;
  return std::floor(positive / (2 * M_PI) * kRotunitTicks) * 2 * M_PI / kRotunitTicks;
}

// ---- magnet ------------------------------------------------------------------------------

namespace {

struct CaptureQuery {
  int group;
  dBodyID found = nullptr;
  std::string name;
};

void capture_callback(void* data, dGeomID capture, dGeomID geom) {
  auto* q = static_cast<CaptureQuery*>(data);
  if (q->found) return;
  const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
  if (!tag || tag->group == q->group || !tag->object || !tag->object->magnetizable) return;
  dBodyID body = dGeomGetBody(geom);
  if (!body) return;
  dContactGeom contact;
  if (dCollide(capture, geom, 1, &contact, sizeof(dContactGeom)) > 0) {
    q->found = body;
    q->name = tag->object->name;
  }
}

}  // namespace

void KurtRobot::run_magnet() {
  if (hold_) {
    // The magnet lets go when what it holds pulls harder than its holding force.
    const Eigen::Vector3d pull(hold_feedback_->f1[0], hold_feedback_->f1[1], hold_feedback_->f1[2]);
    if (pull.norm() > config_.crane_params.holding_force) release("overload");
    return;
  }
  if (!state_.magnet_on) return;
  const Pose magnet = body_pose(magnet_);
  dGeomSetPosition(capture_, magnet.position.x(), magnet.position.y(), magnet.position.z());
  dQuaternion q;
  detail::to_ode(magnet.orientation, q);
  dGeomSetQuaternion(capture_, q);
  CaptureQuery query{chassis_tag_->group, nullptr, {}};
  dSpaceCollide2(capture_, reinterpret_cast<dGeomID>(space_), &query, &capture_callback);
  if (!query.found) return;
  held_body_ = query.found;
  state_.held_object = query.name;
  state_.hold_magnet_at = detail::exact_pose(magnet_);
  state_.hold_object_at = detail::exact_pose(held_body_);
  reattach(held_body_);
  emit(WorldEvent::Type::ObjectAttached, query.name);
}

void KurtRobot::reattach(dBodyID body) {
  if (hold_) dJointDestroy(hold_);
  held_body_ = body;
  if (wake_) {
    wake_(body);
  } else {
    dBodyEnable(body);
  }
  hold_ = dJointCreateFixed(world_, nullptr);
  dJointAttach(hold_, magnet_, body);
  // The joint keeps the two bodies' relative pose at the moment it is set: set it with them
  // where they were when the magnet took hold, then put them back where they are.
  auto framed = [](const detail::ExactPose& p) {
    return p[3] != 0 || p[4] != 0 || p[5] != 0 || p[6] != 0;
  };
  if (framed(state_.hold_magnet_at) && framed(state_.hold_object_at)) {
    const detail::ExactPose magnet_now = detail::exact_pose(magnet_);
    const detail::ExactPose body_now = detail::exact_pose(body);
    detail::set_exact_pose(magnet_, state_.hold_magnet_at);
    detail::set_exact_pose(body, state_.hold_object_at);
    dJointSetFixed(hold_);
    detail::set_exact_pose(magnet_, magnet_now);
    detail::set_exact_pose(body, body_now);
  } else {  // a state given without them: held as they are now
    dJointSetFixed(hold_);
  }
  dJointSetFeedback(hold_, hold_feedback_.get());
}

void KurtRobot::release(const std::string& why) {
  if (hold_) dJointDestroy(hold_);
  hold_ = nullptr;
  held_body_ = nullptr;
  emit(WorldEvent::Type::ObjectReleased, state_.held_object + " (" + why + ")");
  state_.held_object.clear();
}

void KurtRobot::forget_body(dBodyID body) {
  if (hold_ && held_body_ == body) release("object removed");
}

void KurtRobot::emit(WorldEvent::Type type, std::string detail) {
  events_.push_back({type, now_, name(), std::move(detail)});
}

std::vector<WorldEvent> KurtRobot::take_events() {
  std::vector<WorldEvent> out;
  out.swap(events_);
  return out;
}

void KurtRobot::set_state(const State& state, dBodyID held) {
  if (hold_) {
    dJointDestroy(hold_);
    hold_ = nullptr;
    held_body_ = nullptr;
  }
  state_ = state;
  if (held) reattach(held);
}

CraneState KurtRobot::crane_state() const {
  CraneState s;
  s.magnet_on = state_.magnet_on;
  s.held_object = state_.held_object;
  if (config_.crane) {
    s.slew = dJointGetHingeAngle(slew_);
    s.lift = dJointGetHingeAngle(lift_);
    s.hoist = dJointGetSliderPosition(hoist_);
  }
  return s;
}

Pose KurtRobot::magnet_pose() const {
  if (!magnet_) return base_link_pose();
  Pose p = body_pose(magnet_);
  p.position += p.orientation * Eigen::Vector3d(0, 0, -kMagnetHeight / 2);
  return p;
}

std::vector<ShapeView> KurtRobot::shapes() const {
  std::vector<ShapeView> out;
  for (dGeomID g : geoms_) {
    const dBodyID body = dGeomGetBody(g);
    const Color color = body == chassis_  ? Color{0.25f, 0.3f, 0.35f, 1.0f}
                        : body == magnet_ ? Color{0.75f, 0.1f, 0.1f, 1.0f}
                        : body == turret_ || body == boom_
                            ? Color{0.95f, 0.75f, 0.1f, 1.0f}
                            : Color{0.08f, 0.08f, 0.08f, 1.0f};  // tyres
    out.push_back(detail::shape_view(g, color));
  }
  return out;
}

// ---- ground truth ------------------------------------------------------------------------

Pose KurtRobot::base_link_pose() const {
  Pose com = body_pose(chassis_);
  com.position += com.orientation * Eigen::Vector3d(0, 0, config_.body.com_below_base_link);
  return com;
}

Pose KurtRobot::base_footprint_pose() const {
  Pose link = base_link_pose();
  const double drop = config_.body.wheel_axle_below_base_link + config_.drive.wheel_radius();
  link.position += link.orientation * Eigen::Vector3d(0, 0, -drop);
  return link;
}

Eigen::Vector3d KurtRobot::linear_velocity() const {
  return detail::vec(dBodyGetLinearVel(chassis_));
}

Eigen::Vector3d KurtRobot::angular_velocity() const {
  return detail::vec(dBodyGetAngularVel(chassis_));
}

// ---- what the node serves ---------------------------------------------------------------

robot::Capabilities KurtRobot::capabilities() const {
  robot::Capabilities c;
  c.ground_truth = true;
  c.ranges = config_.range_sensors;
  c.imu = true;
  c.rotunit = config_.laser == LaserMount::Rotating;
  c.laser = config_.laser != LaserMount::None;
  c.laser_rotating = config_.laser == LaserMount::Rotating;
  c.points = config_.laser == LaserMount::Rotating;
  c.crane = config_.crane;
  c.magnet = config_.crane;
  return c;
}

robot::Frames KurtRobot::frames() const {
  robot::Frames f;
  const double link_height = config_.body.wheel_axle_below_base_link + config_.drive.wheel_radius();
  f.mounts.push_back(robot_mount("base_footprint", "base_link", {0, 0, link_height}));
  if (config_.range_sensors) {
    for (const RangeSensorSpec& s : kurt_range_sensors()) {
      f.mounts.push_back(
          robot_mount("base_link", s.frame, {s.x, s.y, 0},
                      Eigen::Quaterniond(Eigen::AngleAxisd(s.yaw, Eigen::Vector3d::UnitZ()))));
    }
  }
  if (config_.cameras) add_stereo_frames(*config_.cameras, f);
  if (config_.laser == LaserMount::Fixed) {
    f.mounts.push_back(robot_mount("base_link", "laser", laser_origin(config_.laser)));
  } else if (config_.laser == LaserMount::Rotating) {
    // The scan plane is vertical (the frame's xy plane turned up about x); the rotunit turns
    // it about base_link's z axis.
    f.laser =
        robot_mount("base_link", "laser360", laser_origin(config_.laser),
                    Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX())));
  }
  if (config_.crane) {
    const CraneParams& c = config_.crane_params;
    f.crane_pivot = robot_mount("base_link", "crane_turret", {c.pivot_x, 0, c.pivot_height});
    f.boom_length = c.boom_length;
  }
  f.description = robot::kurt3d::description_text();
  return f;
}

robot::Readings KurtRobot::read(ReadMark& mark, double now) const {
  robot::Readings out;
  out.stamp = now;
  if (state_.frames != mark.frames) {  // every encoder frame
    mark.frames = state_.frames;
    out.odometry = odometry_reading(odometry(), state_.encoder_angle[0], state_.encoder_angle[1]);
    out.ground_truth = ground_truth_reading(*this);
    const ImuReading& imu = state_.imu;
    out.imu = robot::Imu{imu.roll, imu.pitch, imu.yaw, imu.yaw_variance, imu.yaw_rate};
    if (config_.range_sensors) {
      for (const RangeReading& each : state_.ranges) {
        out.ranges.push_back({each.sensor->frame, each.sensor->sonar, each.range});
      }
    }
    if (config_.crane) {
      const CraneState c = crane_state();
      out.crane = robot::Crane{c.slew, c.lift, c.hoist, c.magnet_on, c.held_object};
    }
  }
  if (state_.scans != mark.scans) {  // every sweep
    mark.scans = state_.scans;
    const bool rotating = config_.laser == LaserMount::Rotating;
    out.scan = scan_reading(state_.scan, rotating ? "laser360" : "laser", 1.0 / config_.laser_rate);
    if (rotating) out.rotunit = robot::Rotunit{rotunit_angle(), state_.rotunit_speed};
  }
  if (state_.clouds != mark.clouds) {  // every revolution
    mark.clouds = state_.clouds;
    robot::Cloud c;
    c.xyz.reserve(state_.cloud.points.size() * 3);
    for (const auto& p : state_.cloud.points) c.xyz.insert(c.xyz.end(), {p.x(), p.y(), p.z()});
    out.cloud = std::move(c);
  }
  return out;
}

// ---- its part of the world's state ----------------------------------------------------------

template <class Ar>
void archive(Ar& ar, EncoderCounter& e) {
  e.fields(ar);
}
template <class Ar>
void archive(Ar& ar, KurtOdometry& o) {
  o.fields(ar);
}
template <class Ar>
void archive(Ar& ar, CraneCommand& c) {
  ar(c.slew, c.lift, c.hoist);
}
template <class Ar>
void archive(Ar& ar, RangeReading& r) {
  // The sensor is one of the robot's eight: stored as its index.
  const auto& sensors = kurt_range_sensors();
  int32_t index = r.sensor ? static_cast<int32_t>(r.sensor - sensors.data()) : -1;
  ar(index, r.range);
  if constexpr (Ar::kReading) {
    if (index < -1 || index >= static_cast<int32_t>(sensors.size())) {
      throw std::runtime_error("the snapshot names an unknown range sensor");
    }
    r.sensor = index < 0 ? nullptr : &sensors[static_cast<std::size_t>(index)];
  }
}
template <class Ar>
void archive(Ar& ar, ImuReading& i) {
  ar(i.yaw, i.yaw_rate, i.roll, i.pitch, i.yaw_variance);
}
template <class Ar>
void archive(Ar& ar, PointCloud& c) {
  ar(c.stamp, c.points);
}
template <class Ar>
void archive(Ar& ar, KurtRobot::State& s) {
  ar(s.commanded, s.active, s.last_command_time, s.encoder_angle, s.last_hinge_angle, s.encoders,
     s.odometry, s.next_frame_time, s.frames, s.yaw_unwrapped, s.last_yaw, s.start_yaw, s.crane,
     s.magnet_on, s.held_object, s.hold_magnet_at, s.hold_object_at, s.rotunit_speed,
     s.rotunit_angle, s.cloud_start_angle, s.next_scan_time, s.scans, s.clouds, s.noise_rng,
     s.ranges, s.imu, s.scan, s.cloud, s.cloud_in_progress);
}

std::vector<uint8_t> KurtRobot::save_state() const { return detail::to_bytes(state_); }

std::optional<std::string> KurtRobot::state_problem(const std::vector<uint8_t>& bytes) const {
  State r;
  try {
    r = detail::from_bytes<State>(bytes);
  } catch (const std::runtime_error& e) {
    return std::string(e.what());
  }
  const bool finite = std::isfinite(r.commanded.left) && std::isfinite(r.commanded.right) &&
                      std::isfinite(r.active.left) && std::isfinite(r.active.right) &&
                      std::isfinite(r.crane.slew) && std::isfinite(r.crane.lift) &&
                      std::isfinite(r.crane.hoist) && std::isfinite(r.rotunit_speed) &&
                      std::isfinite(r.rotunit_angle);
  if (!finite) return std::string("a robot whose commands are not finite");
  if (!detail::all_plausible({r.encoder_angle[0], r.encoder_angle[1], r.last_hinge_angle[0],
                              r.last_hinge_angle[1], r.yaw_unwrapped, r.last_yaw, r.start_yaw,
                              r.rotunit_angle, r.cloud_start_angle, r.next_frame_time,
                              r.next_scan_time, r.last_command_time})) {
    return std::string("a robot whose angles or times are not plausible");
  }
  if (!detail::plausible_generator(r.noise_rng)) {
    return std::string("a robot whose noise generator cannot run");
  }
  for (const auto* pose : {&r.hold_magnet_at, &r.hold_object_at}) {
    double norm = 0;
    for (std::size_t i = 3; i < 7; ++i) norm += (*pose)[i] * (*pose)[i];
    for (double v : *pose) {
      if (!std::isfinite(v) || std::abs(v) > 1e5)
        return std::string("a hold that is not plausible");
    }
    if (norm != 0 && std::abs(norm - 1) > 1e-6) return std::string("a hold that is not plausible");
  }
  return std::nullopt;
}

void KurtRobot::load_state(const std::vector<uint8_t>& bytes, const BodyByName& body_of) {
  const State s = detail::from_bytes<State>(bytes);
  set_state(s, s.held_object.empty() ? nullptr : body_of(s.held_object));
}

// ---- the KURT types ----------------------------------------------------------------------

KurtConfig kurt3d_config() { return KurtConfig{}; }  // defaults: crane, rotating laser, cameras

KurtConfig kurt2_config() {
  KurtConfig kurt2;
  kurt2.crane = false;
  kurt2.laser = LaserMount::Fixed;
  kurt2.cameras.reset();  // the KURT2 has no stereo pair
  return kurt2;
}

RobotFactory kurt_factory(KurtConfig config) {
  return [config](const RobotSpec& spec, const RobotBuild& build) -> std::unique_ptr<RobotModel> {
    return std::make_unique<KurtRobot>(spec, build, config);
  };
}

namespace {
std::mutex& kurt_types_mutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, std::shared_ptr<const KurtConfig>>& kurt_types() {
  static std::map<std::string, std::shared_ptr<const KurtConfig>> types{
      {"kurt3d", std::make_shared<const KurtConfig>(kurt3d_config())},
      {"kurt2", std::make_shared<const KurtConfig>(kurt2_config())}};
  return types;
}
}  // namespace

void register_kurt_type(const std::string& type, const KurtConfig& config) {
  {
    std::lock_guard<std::mutex> lock(kurt_types_mutex());
    kurt_types()[type] = std::make_shared<const KurtConfig>(config);
  }
  register_robot_type(type, kurt_factory(config));
}

const KurtConfig* find_kurt_type(const std::string& type) {
  std::lock_guard<std::mutex> lock(kurt_types_mutex());
  auto found = kurt_types().find(type);
  return found == kurt_types().end() ? nullptr : found->second.get();
}

}  // namespace macsim
