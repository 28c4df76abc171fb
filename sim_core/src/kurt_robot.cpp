#include "macsim/sim_core/kurt_robot.h"

#include <ode/ode.h>

#include <cmath>

#include "ode_support.h"

namespace macsim {

using detail::body_pose;
using detail::GeomTag;
using detail::set_body_pose;

namespace {

constexpr int kLeftMiddle = 1;
constexpr int kRightMiddle = 4;

double wrap_difference(double a, double b) {
  return std::remainder(a - b, 2.0 * M_PI);
}

}  // namespace

KurtRobot::KurtRobot(dWorldID world, dSpaceID space, const RobotSpec& spec, int collision_group,
                     KurtDriveParams drive, KurtBodyParams body)
    : name_(spec.name),
      spec_(spec),
      drive_(drive),
      body_(body),
      chassis_tag_(std::make_unique<GeomTag>(GeomTag{collision_group, 0.5, 0.0, 0.1})),
      wheel_tag_(std::make_unique<GeomTag>(
          GeomTag{collision_group, body.wheel_friction, 0.0, 0.1})),
      state_{{}, {}, -1e9, {}, {},
             {EncoderCounter(drive.ticks_per_turn), EncoderCounter(drive.ticks_per_turn)},
             KurtOdometry(drive), drive.frame_period, 0} {
  detail::ensure_ode_ready();
  const double r = drive_.wheel_radius();
  const Eigen::Quaterniond q = spec.pose.orientation;
  const Eigen::Vector3d base_link =
      spec.pose.position + q * Eigen::Vector3d(0, 0, body_.wheel_axle_below_base_link + r);

  // Chassis: one body at the centre of mass, the collision box centred on base_link.
  chassis_ = dBodyCreate(world);
  set_body_pose(chassis_, {base_link + q * Eigen::Vector3d(0, 0, -body_.com_below_base_link), q});
  dMass mass;
  dMassSetParameters(&mass, body_.base_mass, 0, 0, 0, body_.base_inertia.x(),
                     body_.base_inertia.y(), body_.base_inertia.z(), 0, 0, 0);
  dBodySetMass(chassis_, &mass);
  dBodySetAutoDisableFlag(chassis_, 0);
  geoms_[6] = dCreateBox(space, body_.base_size.x(), body_.base_size.y(), body_.base_size.z());
  dGeomSetBody(geoms_[6], chassis_);
  dGeomSetOffsetPosition(geoms_[6], 0, 0, body_.com_below_base_link);
  dGeomSetData(geoms_[6], chassis_tag_.get());

  // Wheels: cylinders (ODE's axis is local z, turned onto the robot's y) on hinge motors.
  const Eigen::Quaterniond wheel_q =
      q * Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitY();
  const double xs[3] = {body_.wheel_x, 0.0, -body_.wheel_x};
  for (int i = 0; i < 6; ++i) {
    const double y = i < 3 ? body_.wheel_y : -body_.wheel_y;
    const Eigen::Vector3d centre =
        base_link + q * Eigen::Vector3d(xs[i % 3], y, -body_.wheel_axle_below_base_link);
    dBodyID wheel = dBodyCreate(world);
    set_body_pose(wheel, {centre, wheel_q});
    dMass wheel_mass;
    dMassSetCylinderTotal(&wheel_mass, body_.wheel_mass, 3, r, body_.wheel_width);
    dBodySetMass(wheel, &wheel_mass);
    dBodySetAutoDisableFlag(wheel, 0);
    dGeomID geom = dCreateCylinder(space, r, body_.wheel_width);
    dGeomSetBody(geom, wheel);
    dGeomSetData(geom, wheel_tag_.get());

    // Attached (wheel, chassis): the motor's velocity is the wheel's rate about +y relative
    // to the chassis, so a positive rate rolls the robot forwards.
    dJointID hinge = dJointCreateHinge(world, nullptr);
    dJointAttach(hinge, wheel, chassis_);
    dJointSetHingeAnchor(hinge, centre.x(), centre.y(), centre.z());
    dJointSetHingeAxis(hinge, axis.x(), axis.y(), axis.z());
    dJointSetHingeParam(hinge, dParamFMax, body_.wheel_torque);
    dJointSetHingeParam(hinge, dParamVel, 0.0);
    wheels_[i] = wheel;
    hinges_[i] = hinge;
    geoms_[i] = geom;
  }
}

KurtRobot::~KurtRobot() {
  for (dJointID h : hinges_) dJointDestroy(h);
  for (dGeomID g : geoms_) dGeomDestroy(g);
  for (dBodyID b : wheels_) dBodyDestroy(b);
  dBodyDestroy(chassis_);
}

void KurtRobot::command_twist(double linear, double angular, double now) {
  command_wheel_speeds(wheel_speeds_from_twist(linear, angular, drive_), now);
}

void KurtRobot::command_wheel_speeds(WheelSpeeds speeds, double now) {
  state_.commanded = quantize_to_speed_cm(speeds);
  state_.last_command_time = now;
}

void KurtRobot::before_step(double now) {
  const bool fresh = now - state_.last_command_time < drive_.command_timeout;
  state_.active = fresh ? state_.commanded : WheelSpeeds{};
  const double r = drive_.wheel_radius();
  for (int i = 0; i < 6; ++i) {
    const double rim_speed = i < 3 ? state_.active.left : state_.active.right;
    dJointSetHingeParam(hinges_[i], dParamVel, rim_speed / r);
  }
}

void KurtRobot::update_wheel_angles() {
  const int middles[2] = {kLeftMiddle, kRightMiddle};
  for (int side = 0; side < 2; ++side) {
    const double angle = dJointGetHingeAngle(hinges_[middles[side]]);
    state_.encoder_angle[side] += wrap_difference(angle, state_.last_hinge_angle[side]);
    state_.last_hinge_angle[side] = angle;
  }
}

void KurtRobot::after_step(double now) {
  update_wheel_angles();
  if (now + 1e-9 < state_.next_frame_time) return;
  state_.next_frame_time += drive_.frame_period;
  const int left = state_.encoders[0].ticks_since_last(state_.encoder_angle[0]);
  const int right = state_.encoders[1].ticks_since_last(state_.encoder_angle[1]);
  state_.odometry.integrate_frame(left, right);
  ++state_.frames;
}

std::array<dBodyID, 7> KurtRobot::bodies() const {
  return {chassis_, wheels_[0], wheels_[1], wheels_[2], wheels_[3], wheels_[4], wheels_[5]};
}

Pose KurtRobot::base_footprint_pose() const {
  Pose com = body_pose(chassis_);
  const double drop =
      body_.com_below_base_link - body_.wheel_axle_below_base_link - drive_.wheel_radius();
  com.position += com.orientation * Eigen::Vector3d(0, 0, drop);
  return com;
}

Eigen::Vector3d KurtRobot::linear_velocity() const {
  return detail::vec(dBodyGetLinearVel(chassis_));
}

Eigen::Vector3d KurtRobot::angular_velocity() const {
  return detail::vec(dBodyGetAngularVel(chassis_));
}

}  // namespace macsim
