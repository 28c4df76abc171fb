#include "macsim/sim_core/diff_drive_robot.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "drive_command.h"
#include "ode_support.h"
#include "ray_caster.h"
#include "robot_readings.h"
#include "state_archive.h"

namespace macsim {

using detail::GeomTag;
using detail::make_robot_body;
using detail::wrap_angle;

namespace {

/// The chassis box's centre above base_link (its bottom clears the floor by 2 cm).
double chassis_above_base_link(const DiffDriveConfig& c) {
  return c.base_size.z() / 2 - c.wheel_radius + 0.02;
}

}  // namespace

RobotFactory diff_drive_factory(DiffDriveConfig config) {
  return [config](const RobotSpec& spec, const RobotBuild& build) -> std::unique_ptr<RobotModel> {
    return std::make_unique<DiffDriveRobot>(spec, build, config);
  };
}

DiffDriveRobot::DiffDriveRobot(const RobotSpec& spec, const RobotBuild& build,
                               const DiffDriveConfig& config)
    : RobotModel(spec),
      config_(config),
      chassis_tag_(
          std::make_unique<GeomTag>(GeomTag{build.collision_group, 0.5, 0.0, 0.1, nullptr})),
      wheel_tag_(
          std::make_unique<GeomTag>(GeomTag{build.collision_group, 1.0, 0.0, 0.1, nullptr})),
      caster_tag_(
          std::make_unique<GeomTag>(GeomTag{build.collision_group, 0.0, 0.0, 0.1, nullptr})),
      rays_(std::make_unique<detail::RayCaster>(build.space, build.collision_group)) {
  detail::ensure_ode_ready();
  const DiffDriveConfig& c = config_;
  const Eigen::Quaterniond q = spec.pose.orientation;
  const Eigen::Vector3d base_link = spec.pose.position + q * Eigen::Vector3d(0, 0, c.wheel_radius);

  // The chassis: a box above base_link, with a frictionless ball under each end.
  const double lift = chassis_above_base_link(c);
  dMass mass;
  dMassSetBoxTotal(&mass, c.base_mass, c.base_size.x(), c.base_size.y(), c.base_size.z());
  chassis_ = make_robot_body(build.world, {base_link + q * Eigen::Vector3d(0, 0, lift), q}, mass);
  dGeomID box = dCreateBox(build.space, c.base_size.x(), c.base_size.y(), c.base_size.z());
  dGeomSetBody(box, chassis_);
  dGeomSetData(box, chassis_tag_.get());
  geoms_.push_back(box);
  const double caster_x = c.base_size.x() / 2 - c.caster_radius;
  for (double x : {caster_x, -caster_x}) {
    dGeomID ball = dCreateSphere(build.space, c.caster_radius);
    dGeomSetBody(ball, chassis_);
    dGeomSetOffsetPosition(ball, x, 0, -lift - c.wheel_radius + c.caster_radius);
    dGeomSetData(ball, caster_tag_.get());
    geoms_.push_back(ball);
  }

  // The wheels on hinge motors about the robot's y axis (a positive rate rolls it forwards).
  const Eigen::Quaterniond wheel_q =
      q * Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitY();
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector3d centre =
        base_link + q * Eigen::Vector3d(0, side == 0 ? c.track / 2 : -c.track / 2, 0);
    dMass wheel_mass;
    dMassSetCylinderTotal(&wheel_mass, c.wheel_mass, 3, c.wheel_radius, c.wheel_width);
    wheels_[side] = make_robot_body(build.world, {centre, wheel_q}, wheel_mass);
    dGeomID geom = dCreateCylinder(build.space, c.wheel_radius, c.wheel_width);
    dGeomSetBody(geom, wheels_[side]);
    dGeomSetData(geom, wheel_tag_.get());
    geoms_.push_back(geom);
    hinges_[side] = dJointCreateHinge(build.world, nullptr);
    dJointAttach(hinges_[side], wheels_[side], chassis_);
    dJointSetHingeAnchor(hinges_[side], centre.x(), centre.y(), centre.z());
    dJointSetHingeAxis(hinges_[side], axis.x(), axis.y(), axis.z());
    dJointSetHingeParam(hinges_[side], dParamFMax, c.wheel_torque);
    dJointSetHingeParam(hinges_[side], dParamVel, 0.0);
  }
  state_.noise_rng.seed(build.noise_seed);
  state_.next_odometry_time = 1.0 / c.odometry_rate;
  state_.next_scan_time = 1.0 / c.laser_rate;
  state_.scan.range_min = c.laser_range_min;
  state_.scan.range_max = c.laser_range_max;
}

DiffDriveRobot::~DiffDriveRobot() {
  for (dJointID h : hinges_) dJointDestroy(h);
  for (dGeomID g : geoms_) dGeomDestroy(g);
  for (dBodyID b : bodies()) dBodyDestroy(b);
}

std::vector<dBodyID> DiffDriveRobot::bodies() const { return {chassis_, wheels_[0], wheels_[1]}; }

// ---- commands and stepping ------------------------------------------------------------------

bool DiffDriveRobot::execute(const robot::RobotCommand& command, double now) {
  return detail::execute_drive(*this, command, now);
}

void DiffDriveRobot::command_twist(double linear, double angular, double now) {
  const double turn = angular * config_.track / 2;
  command_wheel_speeds({linear - turn, linear + turn}, now);
}

void DiffDriveRobot::command_wheel_speeds(WheelSpeeds speeds, double now) {
  const double top = config_.max_speed;
  state_.commanded = {std::clamp(speeds.left, -top, top), std::clamp(speeds.right, -top, top)};
  state_.last_command_time = now;
}

void DiffDriveRobot::keep_command(double now) {
  if (now - state_.last_command_time < config_.command_timeout) state_.last_command_time = now;
}

void DiffDriveRobot::before_step(double now) {
  const bool fresh = now - state_.last_command_time < config_.command_timeout;
  const WheelSpeeds active = fresh ? state_.commanded : WheelSpeeds{};
  dJointSetHingeParam(hinges_[0], dParamVel, active.left / config_.wheel_radius);
  dJointSetHingeParam(hinges_[1], dParamVel, active.right / config_.wheel_radius);
}

void DiffDriveRobot::after_step(double now, double /*step*/) {
  for (int side = 0; side < 2; ++side) {
    const double angle = dJointGetHingeAngle(hinges_[side]);
    state_.wheel_angle[side] += wrap_angle(angle - state_.last_hinge_angle[side]);
    state_.last_hinge_angle[side] = angle;
  }
  if (now + 1e-9 >= state_.next_scan_time) {
    state_.next_scan_time += 1.0 / config_.laser_rate;
    sweep_laser(now);
  }
  if (now + 1e-9 < state_.next_odometry_time) return;
  // Dead reckoning of an ideal differential drive, at the middle of each interval.
  const double period = 1.0 / config_.odometry_rate;
  state_.next_odometry_time += period;
  const double left = (state_.wheel_angle[0] - state_.odometry_angle[0]) * config_.wheel_radius;
  const double right = (state_.wheel_angle[1] - state_.odometry_angle[1]) * config_.wheel_radius;
  state_.odometry_angle = state_.wheel_angle;
  const double distance = (left + right) / 2, turn = (right - left) / config_.track;
  PlanarOdometry& o = state_.odometry;
  const double heading = o.yaw + turn / 2;
  o.x += distance * std::cos(heading);
  o.y += distance * std::sin(heading);
  o.yaw = wrap_angle(o.yaw + turn);
  o.linear = distance / period;
  o.angular = turn / period;
  ++state_.frames;
}

void DiffDriveRobot::sweep_laser(double now) {
  const DiffDriveConfig& c = config_;
  const Pose base = base_link_pose();
  LaserScan& scan = state_.scan;
  scan.stamp = now;
  scan.origin = c.laser_position;
  scan.angle_min = -c.laser_fov / 2;
  scan.angle_increment = c.laser_beams > 1 ? c.laser_fov / (c.laser_beams - 1) : 0.0;
  std::vector<Eigen::Vector3d> directions(static_cast<std::size_t>(c.laser_beams));
  for (int i = 0; i < c.laser_beams; ++i) {
    const double a = scan.angle_min + i * scan.angle_increment;
    directions[i] = base.orientation * Eigen::Vector3d(std::cos(a), std::sin(a), 0);
  }
  const auto hits =
      rays_->cast_fan(base.position + base.orientation * c.laser_position, directions,
                      c.laser_range_max);
  scan.ranges.assign(directions.size(), std::numeric_limits<float>::infinity());
  detail::SweepNoise noise(state_.noise_rng, c.laser_noise);
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i] || *hits[i] < c.laser_range_min) continue;
    scan.ranges[i] = static_cast<float>(*hits[i] + noise());
  }
  ++state_.scans;
}

// ---- ground truth ------------------------------------------------------------------------

Pose DiffDriveRobot::base_link_pose() const {
  Pose p = detail::body_pose(chassis_);
  p.position += p.orientation * Eigen::Vector3d(0, 0, -chassis_above_base_link(config_));
  return p;
}

Pose DiffDriveRobot::base_footprint_pose() const {
  Pose p = base_link_pose();
  p.position += p.orientation * Eigen::Vector3d(0, 0, -config_.wheel_radius);
  return p;
}

Eigen::Vector3d DiffDriveRobot::linear_velocity() const {
  return detail::vec(dBodyGetLinearVel(chassis_));
}

Eigen::Vector3d DiffDriveRobot::angular_velocity() const {
  return detail::vec(dBodyGetAngularVel(chassis_));
}

// ---- what the node serves ---------------------------------------------------------------

robot::Capabilities DiffDriveRobot::capabilities() const {
  robot::Capabilities c;
  c.ground_truth = true;
  c.laser = true;
  return c;
}

robot::Frames DiffDriveRobot::frames() const {
  robot::Frames f;
  f.mounts.push_back(
      detail::robot_mount("base_footprint", "base_link", {0, 0, config_.wheel_radius}));
  f.mounts.push_back(detail::robot_mount("base_link", "laser", config_.laser_position));
  std::ostringstream text;
  text.precision(10);
  const DiffDriveConfig& c = config_;
  text << "robot diff_drive\nbase_size " << c.base_size.x() << " " << c.base_size.y() << " "
       << c.base_size.z() << "\nbase_mass " << c.base_mass << "\nwheel_radius "
       << c.wheel_radius << "\nwheel_width " << c.wheel_width << "\ntrack " << c.track
       << "\nmax_speed " << c.max_speed << "\ncommand_timeout " << c.command_timeout
       << "\nlaser " << c.laser_position.x() << " " << c.laser_position.y() << " "
       << c.laser_position.z() << "\nlaser_beams " << c.laser_beams << "\nlaser_fov "
       << c.laser_fov << "\nlaser_rate " << c.laser_rate << "\nlaser_range " << c.laser_range_min
       << " " << c.laser_range_max << "\n";
  f.description = text.str();
  return f;
}

robot::Readings DiffDriveRobot::read(ReadMark& mark, double now) const {
  robot::Readings out;
  out.stamp = now;
  if (state_.frames != mark.frames) {
    mark.frames = state_.frames;
    out.odometry =
        detail::odometry_reading(state_.odometry, state_.wheel_angle[0], state_.wheel_angle[1]);
    out.ground_truth = detail::ground_truth_reading(*this);
  }
  if (state_.scans != mark.scans) {
    mark.scans = state_.scans;
    out.scan = detail::scan_reading(state_.scan, "laser", 1.0 / config_.laser_rate);
  }
  return out;
}

std::vector<ShapeView> DiffDriveRobot::shapes() const {
  std::vector<ShapeView> out;
  for (dGeomID g : geoms_) {
    const dBodyID body = dGeomGetBody(g);
    const bool ball = dGeomGetClass(g) == dSphereClass;
    out.push_back(detail::shape_view(g, body == chassis_ && !ball ? Color{0.2f, 0.45f, 0.8f, 1.0f}
                                        : ball                   ? Color{0.6f, 0.6f, 0.6f, 1.0f}
                                                                 : Color{0.08f, 0.08f, 0.08f, 1.0f}));
  }
  return out;
}

// ---- its part of the world's state -------------------------------------------------------

template <class Ar>
void archive(Ar& ar, DiffDriveRobot::State& s) {
  ar(s.commanded, s.last_command_time, s.wheel_angle, s.last_hinge_angle, s.odometry_angle,
     s.odometry, s.next_odometry_time, s.frames, s.next_scan_time, s.scans, s.noise_rng, s.scan);
}

std::vector<uint8_t> DiffDriveRobot::save_state() const { return detail::to_bytes(state_); }

std::optional<std::string> DiffDriveRobot::state_problem(const std::vector<uint8_t>& bytes) const {
  State s;
  try {
    s = detail::from_bytes<State>(bytes);
  } catch (const std::runtime_error& e) {
    return std::string(e.what());
  }
  if (!std::isfinite(s.commanded.left) || !std::isfinite(s.commanded.right) ||
      !std::isfinite(s.odometry.x) || !std::isfinite(s.odometry.y) ||
      !std::isfinite(s.odometry.yaw)) {
    return std::string("a robot whose commands or odometry are not finite");
  }
  if (!detail::all_plausible({s.wheel_angle[0], s.wheel_angle[1], s.last_hinge_angle[0],
                              s.last_hinge_angle[1], s.odometry_angle[0], s.odometry_angle[1],
                              s.next_odometry_time, s.next_scan_time, s.last_command_time})) {
    return std::string("a robot whose angles or times are not plausible");
  }
  if (!detail::plausible_generator(s.noise_rng)) {
    return std::string("a robot whose noise generator cannot run");
  }
  return std::nullopt;
}

void DiffDriveRobot::load_state(const std::vector<uint8_t>& bytes, const BodyByName& /*body_of*/) {
  state_ = detail::from_bytes<State>(bytes);
}

}  // namespace macsim
