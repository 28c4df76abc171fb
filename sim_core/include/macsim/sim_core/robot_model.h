// A robot as a plug-in: a type registered by name builds it into an ODE world from a world's
// <ROBOT>; the World steps, saves, restores and draws whatever robots it holds through this
// interface alone, and the robot node serves its readings (macsim/robot/robot_interface.h).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "macsim/robot/robot_interface.h"
#include "macsim/robot/kurt_drive.h"
#include "macsim/sim_core/kurt_sensors.h"
#include "macsim/sim_core/ode_handles.h"
#include "macsim/sim_core/world_event.h"
#include "macsim/sim_core/world_spec.h"

namespace macsim {

/// A stereo camera pair: optical centres in base_link (x forward, y left, z up).
struct StereoMount {
  Pose left, right;
  /// Distance between the optical centres, m.
  double baseline() const { return (left.position - right.position).norm(); }
};

/// Where a robot is built: ODE's world and space, the collision group its geoms carry (no
/// contacts among them) and the seed of its sensor noise.
struct RobotBuild {
  dxWorld* world = nullptr;
  dxSpace* space = nullptr;
  int collision_group = 0;
  uint32_t noise_seed = 1;
  /// Wakes a body of the world (its count of still steps starts again); a robot that takes
  /// hold of a body calls it instead of dBodyEnable, since the world decides sleep.
  std::function<void(dxBody*)> wake;
};

/// What a reader has taken of a robot's readings so far (RobotModel::read), counted in frames,
/// sweeps and clouds; a fresh mark takes whatever the robot produced since it was built.
struct ReadMark {
  uint64_t frames = 0, scans = 0, clouds = 0;
  /// A mark that takes the robot's latest readings whatever their counters (after a reset).
  static ReadMark everything() { return {UINT64_MAX, UINT64_MAX, UINT64_MAX}; }
};

/// The body of a world's object by name, or nullptr (a restored magnet finds what it held).
using BodyByName = std::function<dxBody*(const std::string& object)>;

/// One robot in an ODE world. Commands are set-points (at sim time `now`); the world calls
/// before_step() and after_step() around each step, on the simulation thread.
class RobotModel {
 public:
  virtual ~RobotModel();
  RobotModel(const RobotModel&) = delete;
  RobotModel& operator=(const RobotModel&) = delete;

  const std::string& name() const { return spec_.name; }
  /// The world file's <ROBOT>: name, type, start pose.
  const RobotSpec& spec() const { return spec_; }

  // ---- commands ----------------------------------------------------------------------------
  /// Carries out a command (macsim/robot/robot_command.h: the built-in ones or a plug-in's own)
  /// at sim time `now`; false, changing nothing, for one it does not have.
  virtual bool execute(const robot::RobotCommand& command, double now) = 0;
  /// A drive command still in force at `now` is renewed as if sent again then.
  virtual void keep_command(double now) = 0;

  // ---- stepping -------------------------------------------------------------------------
  /// Applies the motor set-points; before each step that starts at `now`.
  virtual void before_step(double now) = 0;
  /// Reads the sensors; after each step of `step` seconds that ended at `now`.
  virtual void after_step(double now, double step) = 0;
  /// What happened since the last call (its subject is the robot), typed.
  virtual std::vector<WorldEvent> take_events() { return {}; }

  // ---- ground truth and odometry ----------------------------------------------------------
  virtual Pose base_footprint_pose() const = 0;
  virtual Pose base_link_pose() const = 0;
  /// Of the chassis, world frame: m/s and rad/s.
  virtual Eigen::Vector3d linear_velocity() const = 0;
  virtual Eigen::Vector3d angular_velocity() const = 0;
  /// Odometry from the simulated encoders.
  virtual PlanarOdometry odometry() const = 0;

  // ---- what the node serves ----------------------------------------------------------------
  virtual robot::Capabilities capabilities() const = 0;
  /// Its frames (REP-105), from its description: what the node publishes on tf_static.
  virtual robot::Frames frames() const = 0;
  /// The readings newer than `mark` (which it moves on), stamped with `now`.
  virtual robot::Readings read(ReadMark& mark, double now) const = 0;
  /// Its stereo pair, for the renderer; none by default.
  virtual std::optional<StereoMount> cameras() const { return std::nullopt; }

  /// Its shapes where they are now, for drawing.
  virtual std::vector<ShapeView> shapes() const = 0;

  // ---- its part of the world's state (its own archive() field list) ------------------------
  virtual std::vector<uint8_t> save_state() const = 0;
  /// Why `bytes` cannot be this robot's state (damaged, not finite), or nothing.
  virtual std::optional<std::string> state_problem(const std::vector<uint8_t>& bytes) const = 0;
  /// Puts save_state()'s bytes back (checked by state_problem() first).
  virtual void load_state(const std::vector<uint8_t>& bytes, const BodyByName& body_of) = 0;

  // ---- ODE's side, for the world ---------------------------------------------------------
  /// Every body, in a fixed order (their states are saved with the world's).
  virtual std::vector<dxBody*> bodies() const = 0;
  /// An object's body is about to be destroyed: let go of it if the robot holds it.
  virtual void forget_body(dxBody* /*body*/) {}

 protected:
  explicit RobotModel(RobotSpec spec) : spec_(std::move(spec)) {}

 private:
  RobotSpec spec_;
};

/// Builds a robot of one type at its spec's pose.
using RobotFactory =
    std::function<std::unique_ptr<RobotModel>(const RobotSpec& spec, const RobotBuild& build)>;

/// Registers (or replaces) a robot type (the seed's registerRobotType). Built in: "kurt3d",
/// "kurt2" (kurt_robot.h) and "diff_drive" (diff_drive_robot.h).
void register_robot_type(const std::string& type, RobotFactory factory);
/// True if a type of that name is registered.
bool robot_type_known(const std::string& type);
/// Names of the registered types, sorted.
std::vector<std::string> robot_type_names();
/// A robot of its spec's type; throws std::invalid_argument for an unknown type.
std::unique_ptr<RobotModel> build_robot(const RobotSpec& spec, const RobotBuild& build);

}  // namespace macsim
