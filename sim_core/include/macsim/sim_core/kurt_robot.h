// The simulated KURT3D in ODE: chassis, six wheels on torque-limited hinge motors, encoders
// and odometry as the real driver computes them.
#pragma once

#include <ode/common.h>

#include <array>
#include <memory>
#include <string>

#include "macsim/sim_core/kurt_drive.h"
#include "macsim/sim_core/world_spec.h"

namespace macsim {

namespace detail {
struct GeomTag;
}

/// Physical parameters of the simulated KURT3D (see sim_core/README.md for the sources).
struct KurtBodyParams {
  double base_mass = 15.6;                                   ///< kg, URDF base_link
  Eigen::Vector3d base_inertia{0.1185, 0.1928, 0.2402};      ///< kg m^2 about the CoM, URDF
  Eigen::Vector3d base_size{0.43, 0.325, 0.215};             ///< m, URDF collision box
  double com_below_base_link = 0.0404;                       ///< m, URDF CoM z = -0.0404
  double wheel_axle_below_base_link = 0.107;                 ///< m, URDF wheel joint z
  double wheel_x = 0.14;                                     ///< m, front/rear axle from centre
  double wheel_y = 0.14;                                     ///< m, half track
  double wheel_width = 0.035;                                ///< m, indoor URDF
  double wheel_mass = 0.075;                                 ///< kg, indoor URDF
  double wheel_friction = 1.0;                               ///< Coulomb mu of the tyres
  double wheel_torque = 4.0;                                 ///< N m per wheel motor (Gazebo plugin)
};

/// One KURT3D in an ODE world. Commands are set-points; the motors act in before_step().
class KurtRobot {
 public:
  /// Everything of the robot that changes besides its bodies: commands, encoders, odometry.
  struct ControllerState {
    WheelSpeeds commanded{};
    WheelSpeeds active{};
    double last_command_time = -1e9;
    std::array<double, 2> encoder_angle{};     ///< unwrapped middle-wheel angles
    std::array<double, 2> last_hinge_angle{};  ///< wrapped, for unwrapping
    std::array<EncoderCounter, 2> encoders;
    KurtOdometry odometry;
    double next_frame_time;
    uint64_t frames = 0;
  };

  /// Builds the robot at its spec's pose; geoms carry `collision_group` (no self-contacts).
  KurtRobot(dWorldID world, dSpaceID space, const RobotSpec& spec, int collision_group,
            KurtDriveParams drive = {}, KurtBodyParams body = {});
  ~KurtRobot();
  KurtRobot(const KurtRobot&) = delete;
  KurtRobot& operator=(const KurtRobot&) = delete;

  const std::string& name() const { return name_; }

  /// cmd_vel at sim time `now`: mapped to wheel speeds as the real driver maps it.
  void command_twist(double linear, double angular, double now);
  /// Wheel rim speeds (m/s) at sim time `now`, sent as SPEED_CM like the real driver.
  void command_wheel_speeds(WheelSpeeds speeds, double now);

  /// Applies the motor set-points (zero after the command timeout); call before each step.
  void before_step(double now);
  /// Reads the encoders and integrates an odometry frame every frame period; call after.
  void after_step(double now);

  /// Ground truth pose of base_footprint (on the floor below the robot's centre).
  Pose base_footprint_pose() const;
  /// Ground truth linear (m/s) and angular (rad/s) velocity of the chassis, world frame.
  Eigen::Vector3d linear_velocity() const;
  Eigen::Vector3d angular_velocity() const;

  /// Odometry from the simulated encoders, as the real driver computes it.
  PlanarOdometry odometry() const { return state_.odometry.estimate(); }
  /// Number of ENCODER frames so far; a new odometry estimate exists when it grows.
  uint64_t odometry_frames() const { return state_.frames; }
  /// Wheel speeds the motors currently try to hold (m/s; zero after a timeout).
  WheelSpeeds active_wheel_speeds() const { return state_.active; }
  /// Unwrapped angle (rad) of the middle wheel of the left (0) or right (1) side.
  double wheel_angle(int side) const { return state_.encoder_angle[side]; }

  /// The chassis and the six wheels.
  std::array<dBodyID, 7> bodies() const;
  const ControllerState& controller_state() const { return state_; }
  void set_controller_state(const ControllerState& state) { state_ = state; }
  const RobotSpec& spec() const { return spec_; }

  const KurtDriveParams& drive_params() const { return drive_; }
  const KurtBodyParams& body_params() const { return body_; }

 private:
  void update_wheel_angles();

  std::string name_;
  RobotSpec spec_;
  KurtDriveParams drive_;
  KurtBodyParams body_;
  dBodyID chassis_ = nullptr;
  std::array<dBodyID, 6> wheels_{};   // left front, left middle, left rear, right ...
  std::array<dJointID, 6> hinges_{};
  std::array<dGeomID, 7> geoms_{};
  std::unique_ptr<detail::GeomTag> chassis_tag_, wheel_tag_;
  ControllerState state_;
};

}  // namespace macsim
