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

#include "macsim/robot/kurt3d_description.h"
#include "macsim/robot/kurt_drive.h"
#include "macsim/sim_core/kurt_sensors.h"
#include "macsim/sim_core/robot_model.h"

namespace macsim {

namespace detail {
struct GeomTag;
class RayCaster;
}  // namespace detail

/// Physical parameters of the simulated KURT3D (see sim_core/README.md for the sources).
struct KurtBodyParams {
  double base_mass = robot::kurt3d::kBaseMass;  ///< kg
  Eigen::Vector3d base_inertia{robot::kurt3d::kBaseInertia.data()};  ///< kg m^2 about the CoM
  Eigen::Vector3d base_size{robot::kurt3d::kBaseSize.data()};  ///< m, collision box
  double com_below_base_link = robot::kurt3d::kComBelowBaseLink;  ///< m
  double wheel_axle_below_base_link = robot::kurt3d::kBaseLinkAboveWheelAxle;  ///< m
  double wheel_x = robot::kurt3d::kWheelX;  ///< m, front/rear axle from centre
  double wheel_y = robot::kurt3d::kWheelY;  ///< m, half track
  double wheel_width = robot::kurt3d::kWheelWidth;  ///< m
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
  double boom_length = robot::kurt3d::kBoomLength;  ///< m, pivot to boom tip
  double pivot_height = robot::kurt3d::kPivotHeight;  ///< m above base_link
  double pivot_x = robot::kurt3d::kPivotX;  ///< m ahead of base_link
  double max_hoist = robot::kurt3d::kMaxHoist;  ///< m the magnet can be lowered
  double slew_torque = 3.0;        ///< N m
  double lift_torque = 8.0;        ///< N m
  double hoist_force = 7.0;        ///< N: with the 0.2 kg magnet, lifts up to about 0.5 kg
  double slew_speed = 1.0;         ///< rad/s
  double lift_speed = 0.5;         ///< rad/s
  double hoist_speed = 0.15;       ///< m/s
  double magnet_radius = robot::kurt3d::kMagnetRadius;  ///< m
  double magnet_mass = 0.2;        ///< kg
  double holding_force = 30.0;     ///< N; the magnet lets go above it
  double capture_distance = 0.01;  ///< m; a magnetizable object this close is grabbed
};

/// The KURT3D's stereo pair (its description): a baseline on a mast, looking down over the crane.
StereoMount kurt3d_cameras();

/// Everything a robot type fixes: drive, body, sensors, cameras, crane, noise.
struct KurtConfig {
  KurtDriveParams drive;
  KurtBodyParams body;
  bool crane = true;
  CraneParams crane_params;
  bool range_sensors = true;  ///< IR and sonar, read with every encoder frame (100 Hz)
  std::optional<StereoMount> cameras = kurt3d_cameras();  ///< none without a stereo pair
  LaserMount laser = LaserMount::Rotating;
  double laser_rate = robot::kurt3d::kLaserRate;  ///< Hz, LMS200 sweeps
  double laser_noise = 0.005;  ///< m, Gaussian sigma of each beam
  double rotunit_speed = 0.0;  ///< rad/s at start (the driver's default is pi/6 when used)
  double gyro_noise = 0.0;     ///< rad, Gaussian sigma of each yaw reading
  double gyro_drift = 0.0;     ///< rad/s
  uint32_t noise_seed = 1;
};

/// One KURT in an ODE world, a RobotModel of type "kurt3d", "kurt2" or one registered with
/// register_kurt_type(). Commands are set-points; motors act in before_step(), sensors are read
/// in after_step(), both on the simulation thread.
class KurtRobot final : public RobotModel {
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
    /// The magnet's and the held body's poses when it took hold (x y z, qw qx qy qz, as ODE
    /// held them): a restore makes the hold again from them, bit for bit.
    std::array<double, 7> hold_magnet_at{}, hold_object_at{};
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

  /// Builds the robot at its spec's pose (encoder frames at the spec's encoder rate).
  KurtRobot(const RobotSpec& spec, const RobotBuild& build, const KurtConfig& config);
  ~KurtRobot() override;

  const KurtConfig& config() const { return config_; }

  // ---- commands -------------------------------------------------------------------------
  /// Twist, wheel speeds; the rotunit's speed if its laser turns; the crane and the magnet if
  /// it has the crane. The rest is refused.
  bool execute(const robot::RobotCommand& command, double now) override;
  /// cmd_vel at sim time `now`: mapped to wheel speeds as the real driver maps it.
  void command_twist(double linear, double angular, double now);
  /// Wheel rim speeds (m/s) at sim time `now`, sent as SPEED_CM like the real driver.
  void command_wheel_speeds(WheelSpeeds speeds, double now);
  /// Crane joint targets; the joints move there as fast as their motors allow.
  bool command_crane(const CraneCommand& target);
  /// Switches the magnet; off releases what it holds.
  bool command_magnet(bool on);
  /// Rotating unit speed (rad/s), quantized as the real driver sends it.
  bool command_rotunit(double speed);
  void keep_command(double now) override;

  // ---- stepping -------------------------------------------------------------------------
  /// Applies the motor set-points (zero after the command timeout).
  void before_step(double now) override;
  /// Reads encoders, gyro, ranges and the laser, and runs the magnet.
  void after_step(double now, double step) override;
  /// ObjectAttached and ObjectReleased since the last call.
  std::vector<WorldEvent> take_events() override;

  // ---- ground truth ---------------------------------------------------------------------
  Pose base_footprint_pose() const override;
  Pose base_link_pose() const override;
  Eigen::Vector3d linear_velocity() const override;
  Eigen::Vector3d angular_velocity() const override;

  // ---- what the node serves -------------------------------------------------------------
  robot::Capabilities capabilities() const override;
  /// base_link above base_footprint, the IR/sonar sensors, the stereo cameras (and their
  /// optical frames), the laser, the crane.
  robot::Frames frames() const override;
  /// Odometry, ground truth, IMU, ranges and crane with every encoder frame, a scan (and the
  /// rotunit) with every sweep, a cloud with every revolution.
  robot::Readings read(ReadMark& mark, double now) const override;
  std::optional<StereoMount> cameras() const override { return config_.cameras; }

  // ---- proprioception and sensors ------------------------------------------------------
  /// Odometry from the simulated encoders, as the real driver computes it.
  PlanarOdometry odometry() const override { return state_.odometry.estimate(); }
  /// Rotunit angle (rad in [0, 2 pi)) as its encoder reports it (kRotunitTicks per turn).
  double rotunit_angle() const;
  /// The crane's joints and magnet.
  CraneState crane_state() const;
  /// Pose of the magnet's underside centre (ground truth).
  Pose magnet_pose() const;

  /// The robot's shapes where they are now, for drawing.
  std::vector<ShapeView> shapes() const override;
  /// The robot's state besides its bodies: its commands and the motors' speeds (`active`), encoder
  /// frames, wheel angles, the last readings of every sensor (`ranges`, `imu`, `scan`, `cloud`)
  /// and how many there were (`frames`, `scans`, `clouds`).
  const State& state() const { return state_; }
  /// Puts the state back; the magnet holds `held` (the state's held object's body) if given.
  void set_state(const State& state, dxBody* held = nullptr);

  // ---- its part of the world's state ------------------------------------------------------
  std::vector<uint8_t> save_state() const override;
  std::optional<std::string> state_problem(const std::vector<uint8_t>& bytes) const override;
  void load_state(const std::vector<uint8_t>& bytes, const BodyByName& body_of) override;

  // ---- ODE's side -------------------------------------------------------------------------
  /// Every body: the chassis, the six wheels, then the crane's (turret, boom, magnet).
  std::vector<dxBody*> bodies() const override;
  /// Lets go of `body` if the magnet holds it.
  void forget_body(dxBody* body) override;

 private:
  /// Hold `body` with the magnet.
  void reattach(dxBody* body);

  void build_crane(dxWorld* world, dxSpace* space, const Pose& base_link);
  void update_wheel_angles();
  void read_frame_sensors(double now);
  void sweep_laser(double now);
  void run_magnet();
  void release(const std::string& why);
  void emit(WorldEvent::Type type, std::string detail);

  KurtConfig config_;
  dxWorld* world_;
  std::function<void(dxBody*)> wake_;  // the world's (RobotBuild::wake)
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
  std::vector<WorldEvent> events_;
  double now_ = 0.0;  // sim time of the last step, for events

  State state_;
};

/// The built-in KURT types: "kurt3d" (crane with magnet, LMS200 on a rotating unit, stereo
/// pair) and "kurt2" (no crane, no cameras, LMS200 fixed at the front).
KurtConfig kurt3d_config();
KurtConfig kurt2_config();
/// Builds KURTs of that configuration (for register_robot_type()).
RobotFactory kurt_factory(KurtConfig config);
/// Registers (or replaces) a KURT type by its configuration.
void register_kurt_type(const std::string& type, const KurtConfig& config);
/// The configuration of a KURT type, or nullptr if there is no KURT type of that name.
const KurtConfig* find_kurt_type(const std::string& type);

}  // namespace macsim
