// The simulated KURT3D in ODE: chassis, six wheels on torque-limited hinge motors, encoders
// and odometry as the real driver computes them, IR/sonar, gyro and tilt, the laser scanner on
// its rotating unit, and the crane arm with its electromagnet.
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "macsim/sim_core/kurt_drive.h"
#include "macsim/sim_core/kurt_sensors.h"
#include "macsim/sim_core/ode_handles.h"
#include "macsim/sim_core/world_spec.h"

namespace macsim {

namespace detail {
struct GeomTag;
class RayCaster;
}  // namespace detail

/// Physical parameters of the simulated KURT3D (see sim_core/README.md for the sources).
struct KurtBodyParams {
  double base_mass = 15.6;                                      ///< kg, URDF base_link
  Eigen::Vector3d base_inertia{0.1185, 0.1928, 0.2402};         ///< kg m^2 about the CoM, URDF
  Eigen::Vector3d base_size{0.43, 0.325, 0.215};                ///< m, URDF collision box
  double com_below_base_link = 0.0404;                          ///< m, URDF CoM z = -0.0404
  double wheel_axle_below_base_link = kBaseLinkAboveWheelAxle;  ///< m, URDF wheel joint z
  double wheel_x = 0.14;                                        ///< m, front/rear axle from centre
  double wheel_y = 0.14;                                        ///< m, half track
  double wheel_width = 0.035;                                   ///< m, indoor URDF
  double wheel_mass = 0.3;                                      ///< kg (URDF: 0.075; see README)
  double wheel_friction = 1.0;                                  ///< Coulomb mu of the tyres
  double wheel_torque = 4.0;  ///< N m per wheel motor (Gazebo plugin)
};

/// Where the laser scanner sits.
enum class LaserMount {
  None,
  Fixed,     ///< KURT2: an LMS200 scanning the horizontal plane at the front
  Rotating,  ///< KURT3D/KURT360: a vertical scan plane turning about the vertical axis
};

/// Where the laser's scan origin sits in base_link (m): on the rotunit, or fixed at the front.
Eigen::Vector3d laser_origin(LaserMount mount);

/// The crane (our model: the MACS KURT3D's crane is not documented; see sim_core/README.md).
struct CraneParams {
  double boom_length = 0.5;        ///< m, slew axis to boom tip
  double pivot_height = 0.16;      ///< m above base_link
  double pivot_x = 0.05;           ///< m ahead of base_link
  double max_hoist = 0.32;         ///< m the magnet can be lowered
  double slew_torque = 3.0;        ///< N m
  double lift_torque = 8.0;        ///< N m
  double hoist_force = 7.0;        ///< N: with the 0.2 kg magnet, lifts up to about 0.5 kg
  double slew_speed = 1.0;         ///< rad/s
  double lift_speed = 0.5;         ///< rad/s
  double hoist_speed = 0.15;       ///< m/s
  double magnet_radius = 0.035;    ///< m
  double magnet_mass = 0.2;        ///< kg
  double holding_force = 30.0;     ///< N; the magnet lets go above it
  double capture_distance = 0.01;  ///< m; a magnetizable object this close is grabbed
};

/// A stereo camera pair: optical centres in base_link (x forward, y left, z up).
struct StereoMount {
  /// Ours for the KURT3D: a 0.12 m baseline on a mast 0.42 m above base_link, looking 15
  /// degrees down over the crane.
  Pose left{{0.05, 0.06, 0.42},
            Eigen::Quaterniond(Eigen::AngleAxisd(15 * M_PI / 180, Eigen::Vector3d::UnitY()))};
  Pose right{{0.05, -0.06, 0.42},
             Eigen::Quaterniond(Eigen::AngleAxisd(15 * M_PI / 180, Eigen::Vector3d::UnitY()))};
  /// Distance between the optical centres, m.
  double baseline() const { return (left.position - right.position).norm(); }
};

/// Everything a robot type fixes: drive, body, sensors, cameras, crane, noise.
struct KurtConfig {
  KurtDriveParams drive;
  KurtBodyParams body;
  bool crane = true;
  CraneParams crane_params;
  bool range_sensors = true;  ///< IR and sonar, read with every encoder frame (100 Hz)
  std::optional<StereoMount> cameras = StereoMount{};  ///< none on a robot without a stereo pair
  LaserMount laser = LaserMount::Rotating;
  double laser_rate = 75.0;    ///< Hz, LMS200 sweeps
  double laser_noise = 0.005;  ///< m, Gaussian sigma of each beam
  double rotunit_speed = 0.0;  ///< rad/s at start (the driver's default is pi/6 when used)
  double gyro_noise = 0.0;     ///< rad, Gaussian sigma of each yaw reading
  double gyro_drift = 0.0;     ///< rad/s
  uint32_t noise_seed = 1;
};

/// One KURT in an ODE world. Commands are set-points; motors act in before_step(), sensors
/// are read in after_step(), both on the simulation thread.
class KurtRobot {
 public:
  /// Everything of the robot that changes besides its bodies: commands, encoders, odometry,
  /// gyro, crane, magnet, rotunit, the noise generator and the last readings of every sensor.
  struct State {
    WheelSpeeds commanded{};
    WheelSpeeds active{};
    double last_command_time = -1e9;
    std::array<double, 2> encoder_angle{};     ///< unwrapped middle-wheel angles
    std::array<double, 2> last_hinge_angle{};  ///< wrapped, for unwrapping
    std::array<EncoderCounter, 2> encoders;
    KurtOdometry odometry;
    double next_frame_time = 0.0;
    uint64_t frames = 0;
    // gyro
    double yaw_unwrapped = 0.0, last_yaw = 0.0, start_yaw = 0.0;
    // crane and magnet
    CraneCommand crane{};
    bool magnet_on = false;
    std::string held_object;
    // laser on its rotating unit
    double rotunit_speed = 0.0;  ///< rad/s, as quantized by the command
    double rotunit_angle = 0.0;  ///< rad, continuous
    double cloud_start_angle = 0.0;
    double next_scan_time = 0.0;
    uint64_t scans = 0, clouds = 0;
    std::mt19937 noise_rng;  ///< Gaussian sensor noise is drawn from it alone
    // the last readings
    std::array<RangeReading, 8> ranges{};
    ImuReading imu;
    LaserScan scan;
    PointCloud cloud, cloud_in_progress;
  };

  ~KurtRobot();
  KurtRobot(const KurtRobot&) = delete;
  KurtRobot& operator=(const KurtRobot&) = delete;

  const std::string& name() const { return name_; }
  const RobotSpec& spec() const { return spec_; }
  const KurtConfig& config() const { return config_; }

  // ---- commands -------------------------------------------------------------------------
  /// cmd_vel at sim time `now`: mapped to wheel speeds as the real driver maps it.
  void command_twist(double linear, double angular, double now);
  /// Wheel rim speeds (m/s) at sim time `now`, sent as SPEED_CM like the real driver.
  void command_wheel_speeds(WheelSpeeds speeds, double now);
  /// Crane joint targets; the joints move there as fast as their motors allow.
  void command_crane(const CraneCommand& target);
  /// Switches the magnet; off releases what it holds.
  void command_magnet(bool on);
  /// Rotating unit speed (rad/s), quantized as the real driver sends it.
  void command_rotunit(double speed);
  /// A drive command still in force at sim time `now` is renewed as if sent again then.
  void keep_command(double now);

  // ---- stepping -------------------------------------------------------------------------
  /// Applies the motor set-points (zero after the command timeout); call before each step.
  void before_step(double now);
  /// Reads encoders, gyro, ranges and the laser, and runs the magnet; call after each step
  /// of `step` seconds that ended at sim time `now`.
  void after_step(double now, double step);
  /// Events since the last call: {type, detail}, type "attached" or "released".
  std::vector<std::pair<std::string, std::string>> take_events();

  // ---- ground truth ---------------------------------------------------------------------
  /// Ground truth pose of base_footprint (on the floor below the robot's centre).
  Pose base_footprint_pose() const;
  /// Ground truth pose of base_link.
  Pose base_link_pose() const;
  /// Ground truth linear (m/s) and angular (rad/s) velocity of the chassis, world frame.
  Eigen::Vector3d linear_velocity() const;
  Eigen::Vector3d angular_velocity() const;

  // ---- proprioception and sensors ------------------------------------------------------
  /// Odometry from the simulated encoders, as the real driver computes it.
  PlanarOdometry odometry() const { return state_.odometry.estimate(); }
  /// Number of ENCODER frames so far; new odometry, ranges and IMU exist when it grows.
  uint64_t odometry_frames() const { return state_.frames; }
  /// Wheel speeds the motors currently try to hold (m/s; zero after a timeout).
  WheelSpeeds active_wheel_speeds() const { return state_.active; }
  /// Unwrapped angle (rad) of the middle wheel of the left (0) or right (1) side.
  double wheel_angle(int side) const { return state_.encoder_angle[side]; }
  /// The eight IR/sonar readings of the last frame.
  const std::array<RangeReading, 8>& ranges() const { return state_.ranges; }
  /// Gyro yaw and tilt of the last frame.
  const ImuReading& imu() const { return state_.imu; }
  /// The last laser sweep; a new one exists when laser_scans() grows.
  const LaserScan& laser_scan() const { return state_.scan; }
  uint64_t laser_scans() const { return state_.scans; }
  /// The last assembled 3D cloud (one rotunit revolution); new when point_clouds() grows.
  const PointCloud& point_cloud() const { return state_.cloud; }
  uint64_t point_clouds() const { return state_.clouds; }
  /// Rotunit angle (rad in [0, 2 pi)) as its encoder reports it, 10240 ticks per turn.
  double rotunit_angle() const;
  /// The rotunit's speed (rad/s) as its last command was quantized.
  double rotunit_speed() const { return state_.rotunit_speed; }
  /// The crane's joints and magnet.
  CraneState crane_state() const;
  /// Pose of the magnet's underside centre (ground truth).
  Pose magnet_pose() const;

  /// The robot's shapes where they are now, for drawing.
  std::vector<ShapeView> shapes() const;
  /// The robot's state besides its bodies.
  const State& state() const { return state_; }
  /// Puts the state back (a held object is re-attached by reattach()).
  void set_state(const State& state);

 private:
  // ---- ODE's side, for the World that owns the robot ------------------------------------
  friend class World;
  /// Builds the robot at its spec's pose; geoms carry `collision_group` (no self-contacts).
  KurtRobot(dxWorld* world, dxSpace* space, const RobotSpec& spec, int collision_group,
            const KurtConfig& config);
  /// Every body: the chassis, the six wheels, then the crane's (turret, boom, magnet).
  std::vector<dxBody*> bodies() const;
  /// The body of an object about to be destroyed: let go of it if the magnet holds it.
  void forget_body(dxBody* body);
  /// After a restore: hold `body` (the state's held_object) with the magnet again.
  void reattach(dxBody* body);

  void build_crane(dxWorld* world, dxSpace* space, const Pose& base_link);
  void update_wheel_angles();
  void read_frame_sensors(double now);
  void sweep_laser(double now);
  void run_magnet();
  void release(const std::string& why);

  std::string name_;
  RobotSpec spec_;
  KurtConfig config_;
  dxWorld* world_;
  dxSpace* space_;
  dxBody* chassis_ = nullptr;
  std::array<dxBody*, 6> wheels_{};  // left front, left middle, left rear, right ...
  std::array<dxJoint*, 6> hinges_{};
  std::vector<dxGeom*> geoms_;
  std::unique_ptr<detail::GeomTag> chassis_tag_, wheel_tag_, crane_tag_;
  // crane
  dxBody* turret_ = nullptr;
  dxBody* boom_ = nullptr;
  dxBody* magnet_ = nullptr;
  dxJoint* slew_ = nullptr;
  dxJoint* lift_ = nullptr;
  dxJoint* hoist_ = nullptr;
  dxGeom* capture_ = nullptr;  // not in the space: the magnet's reach
  dxJoint* hold_ = nullptr;    // magnet -> held object
  dxBody* held_body_ = nullptr;
  std::unique_ptr<dJointFeedback> hold_feedback_;
  std::unique_ptr<detail::RayCaster> rays_;
  std::vector<std::pair<std::string, std::string>> events_;

  State state_;
};

}  // namespace macsim
