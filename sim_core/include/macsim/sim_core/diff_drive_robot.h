// A plain differential-drive base with one planar laser: the smallest robot type, added through
// the RobotModel interface alone (type "diff_drive" in a world's <ROBOT><TYPE>).
#pragma once

#include <array>
#include <memory>
#include <random>

#include "macsim/sim_core/kurt_sensors.h"
#include "macsim/sim_core/robot_model.h"

namespace macsim {

namespace detail {
struct GeomTag;
class RayCaster;
}  // namespace detail

/// Its description: body, wheels, the laser and its mount (base_link: x forward, y left, z up).
struct DiffDriveConfig {
  Eigen::Vector3d base_size{0.30, 0.24, 0.10};  ///< m, chassis box
  double base_mass = 6.0;                        ///< kg
  double wheel_radius = 0.05;                    ///< m
  double wheel_width = 0.03;                     ///< m
  double wheel_mass = 0.25;                      ///< kg
  double track = 0.28;                           ///< m between the wheels' centres
  double wheel_torque = 0.6;                     ///< N m per wheel motor (below what slips)
  double caster_radius = 0.025;                  ///< m, a frictionless ball at the back
  double max_speed = 1.0;                        ///< m/s at each rim
  double command_timeout = 0.5;                  ///< s without a command: the wheels stop
  double odometry_rate = 50.0;                   ///< Hz
  Eigen::Vector3d laser_position{0.10, 0.0, 0.08};  ///< m, the scan origin above base_link
  int laser_beams = 241;                            ///< over laser_fov, evenly
  double laser_fov = 4 * M_PI / 3;                  ///< rad, centred ahead
  double laser_rate = 10.0;                         ///< Hz
  double laser_range_min = 0.05, laser_range_max = 8.0;  ///< m
  double laser_noise = 0.0;                              ///< m, Gaussian sigma
};

/// Builds diff-drive robots of that configuration (for register_robot_type()).
RobotFactory diff_drive_factory(DiffDriveConfig config);

/// A differential-drive robot in an ODE world.
class DiffDriveRobot final : public RobotModel {
 public:
  /// Everything that changes besides its bodies.
  struct State {
    WheelSpeeds commanded{};
    double last_command_time = -1e9;
    std::array<double, 2> wheel_angle{};       ///< unwrapped, rad
    std::array<double, 2> last_hinge_angle{};  ///< wrapped, for unwrapping
    std::array<double, 2> odometry_angle{};    ///< wheel angles at the last odometry update
    PlanarOdometry odometry;
    double next_odometry_time = 0.0;
    uint64_t frames = 0;
    double next_scan_time = 0.0;
    uint64_t scans = 0;
    std::mt19937 noise_rng;
    LaserScan scan;
  };

  DiffDriveRobot(const RobotSpec& spec, const RobotBuild& build, const DiffDriveConfig& config);
  ~DiffDriveRobot() override;

  const DiffDriveConfig& config() const { return config_; }
  const State& state() const { return state_; }

  /// Twist and wheel speeds; it has nothing else.
  bool execute(const robot::RobotCommand& command, double now) override;
  void command_twist(double linear, double angular, double now);
  void command_wheel_speeds(WheelSpeeds speeds, double now);
  void keep_command(double now) override;
  void before_step(double now) override;
  void after_step(double now, double step) override;

  Pose base_footprint_pose() const override;
  Pose base_link_pose() const override;
  Eigen::Vector3d linear_velocity() const override;
  Eigen::Vector3d angular_velocity() const override;
  PlanarOdometry odometry() const override { return state_.odometry; }

  robot::Capabilities capabilities() const override;
  robot::Frames frames() const override;
  robot::Readings read(ReadMark& mark, double now) const override;
  std::vector<ShapeView> shapes() const override;

  std::vector<uint8_t> save_state() const override;
  std::optional<std::string> state_problem(const std::vector<uint8_t>& bytes) const override;
  void load_state(const std::vector<uint8_t>& bytes, const BodyByName& body_of) override;
  std::vector<dxBody*> bodies() const override;

 private:
  void sweep_laser(double now);

  DiffDriveConfig config_;
  dxBody* chassis_ = nullptr;
  std::array<dxBody*, 2> wheels_{};  // left, right
  std::array<dxJoint*, 2> hinges_{};
  std::vector<dxGeom*> geoms_;
  std::unique_ptr<detail::GeomTag> chassis_tag_, wheel_tag_, caster_tag_;
  std::unique_ptr<detail::RayCaster> rays_;
  State state_;
};

}  // namespace macsim
