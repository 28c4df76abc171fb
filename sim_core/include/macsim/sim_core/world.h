// What ODE holds: a world built from a WorldSpec, stepped at a fixed step, changed on the fly
// through the supervisor operations (the seed's "Simulation Control Interface").
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "macsim/sim_core/data_roots.h"
#include "macsim/sim_core/ode_handles.h"
#include "macsim/sim_core/robot_model.h"
#include "macsim/sim_core/world_bounds.h"
#include "macsim/sim_core/world_event.h"
#include "macsim/sim_core/world_overlaps.h"
#include "macsim/sim_core/world_spec.h"
#include "macsim/sim_core/world_state.h"

namespace macsim {

namespace detail {
struct GeomTag;
class BroadPhase;
struct ObjectRecord;
struct JointRecord;
struct DoorRecord;
class ObjectTable;
class DoorTable;
class WorldPhysics;
}  // namespace detail

/// Stable id of an object: never reused while the world lives (list indices shift, ids do not).
using ObjectId = uint32_t;

/// Why a supervisor operation failed.
enum class ErrorCode {
  Ok = 0,
  UnknownObject,    ///< no object (or door) with that id, index or name
  WrongGeometry,    ///< e.g. set a cylinder's size on a box
  InvalidArgument,  ///< NaN, infinity, negative or zero size, out of range ...
  NotApplicable,    ///< e.g. set the mass of a fixed object
  Penetration,      ///< the change would put the object inside another (refused)
  BadTexture,       ///< not a BMP of 2^n x 2^n pixels with n < 11
  BadFile,          ///< an environment file that cannot be loaded
  LimitReached,     ///< a cap on what requests may make the simulator keep (e.g. snapshots)
};

/// Outcome of a supervisor operation. On error the world is unchanged.
struct Status {
  ErrorCode code = ErrorCode::Ok;
  std::string message;
  std::vector<std::string> penetrated;  ///< objects the change penetrates (when allowed)
  bool ok() const { return code == ErrorCode::Ok; }
  static Status error(ErrorCode code, std::string message) {
    return {code, std::move(message), {}};
  }
};

/// A value or an error.
template <class T>
struct Result {
  Status status;
  T value{};
  bool ok() const { return status.ok(); }
};

/// What to do when a relocated, resized or created object would penetrate another.
enum class PenetrationPolicy {
  Refuse,  ///< leave the world unchanged and return ErrorCode::Penetration
  Allow,   ///< apply it and list the penetrated objects in Status::penetrated
};

/// Pose and velocities of an object (world frame; the pose is the object's frame).
struct ObjectState {
  Pose pose;
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
};

/// The state of a door-switch structure.
struct DoorState {
  bool triggered = false;  ///< pressed fully, or triggered virtually
  bool virtually_triggered = false;
  DoorGap gap = DoorGap::Closed;
  double opening = 0.0;        ///< 0 closed .. 1 fully open
  double switch_travel = 0.0;  ///< 0 up .. 1 pressed fully
};

/// The objects a door is made of.
struct DoorParts {
  ObjectId leaf = 0, frame = 0;
  std::optional<ObjectId> platform, base;  ///< absent for a door without a switch
};

/// How much reset() puts back.
enum class ResetScope {
  Poses,         ///< poses and velocities of loaded objects and robots; time goes on
  PosesAndTime,  ///< that, plus sim time 0 and the random seed
  Everything,    ///< the world as loaded: spawned objects removed, destroyed ones back
};

/// The world's objects, read: found by list index, id, name or user data; their descriptions,
/// states, masses and textures (World::objects()).
class WorldObjects {
 public:
  /// A view of the world's object table (World makes it).
  explicit WorldObjects(const detail::ObjectTable& table) : table_(table) {}
  WorldObjects(const WorldObjects&) = delete;
  WorldObjects& operator=(const WorldObjects&) = delete;

  /// How many objects the world holds.
  int object_count() const;
  /// Id of the object at a list index (indices shift when objects are destroyed).
  std::optional<ObjectId> object_at(int index) const;
  /// List index of an object.
  std::optional<int> index_of(ObjectId id) const;
  /// Id of the object with that name (e.g. "doors/door_00/door_component/leaf").
  std::optional<ObjectId> find_object(const std::string& name) const;
  /// Ids of the objects with that user data, in list order.
  std::vector<ObjectId> find_by_user_data(const std::string& user_data) const;
  /// Ids of every object, in list order.
  std::vector<ObjectId> object_ids() const;

  /// The object's current description (components, density, colours, flags), or nullptr.
  const ObjectSpec* object(ObjectId id) const;
  /// Pose and velocities.
  Result<ObjectState> object_state(ObjectId id) const;
  /// Mass in kg (portable objects).
  Result<double> object_mass(ObjectId id) const;
  /// Inertia tensor about the centre of mass, world-aligned object frame (portable objects).
  Result<Eigen::Matrix3d> object_inertia(ObjectId id) const;
  /// Centre of mass in the object's frame.
  Result<Eigen::Vector3d> object_center_of_mass(ObjectId id) const;
  /// Force and torque accumulated for the next step (world frame).
  Result<std::pair<Eigen::Vector3d, Eigen::Vector3d>> object_wrench(ObjectId id) const;
  /// Texture id (unique per file, 0: none) and file of a component.
  Result<std::pair<int, std::string>> object_texture(ObjectId id, int component = 0) const;

  /// Ok if the object is a free rigid body that takes velocities, forces and torques (not
  /// fixed, frozen, or driven by its door's joint); the error says which and names `what`.
  Status free_body(ObjectId id, const std::string& what) const;

 private:
  const detail::ObjectTable& table_;
  mutable std::vector<std::string> textures_;  // texture id - 1 -> file, in the order asked
};

/// The world's objects, changed: created, imported, destroyed, moved, resized, re-coloured,
/// pushed (World::edit()). On error the world is unchanged.
class WorldEditor {
 public:
  /// Changes the world's object table and doors, building in ODE through `physics` (World
  /// makes it).
  WorldEditor(detail::ObjectTable& table, detail::DoorTable& doors, detail::WorldPhysics& physics)
      : table_(table), doors_(doors), physics_(physics) {}
  WorldEditor(const WorldEditor&) = delete;
  WorldEditor& operator=(const WorldEditor&) = delete;

  /// Adds a basic, composite or ramp object (name made unique if empty).
  Result<ObjectId> create_object(ObjectSpec spec,
                                 PenetrationPolicy policy = PenetrationPolicy::Allow);
  /// Adds every object, joint and door of an environment file, as an <IMPORT> with that id
  /// and pose would; returns the new objects' ids. All or nothing.
  Result<std::vector<ObjectId>> import_environment(const std::string& file, const std::string& id,
                                                   const Pose& pose);
  /// Adds the objects, joints and doors of an environment already loaded (names made by its
  /// import id), placed at `pose`; returns the new objects' ids. All or nothing.
  Result<std::vector<ObjectId>> add_environment(WorldSpec environment, const Pose& pose);
  Status destroy_object(ObjectId id);
  /// Destroys the objects with that user data; returns how many.
  int destroy_objects(const std::string& user_data);
  int destroy_all_objects();
  int destroy_all_portable_objects();
  int destroy_all_fixed_objects();

  Status set_pose(ObjectId id, const Pose& pose,
                  PenetrationPolicy policy = PenetrationPolicy::Refuse);
  Status set_position(ObjectId id, const Eigen::Vector3d& position,
                      PenetrationPolicy policy = PenetrationPolicy::Refuse);
  Status set_orientation(ObjectId id, const Eigen::Quaterniond& orientation,
                         PenetrationPolicy policy = PenetrationPolicy::Refuse);
  /// Sizes of a box component (full sizes, m).
  Status set_box_size(ObjectId id, int component, const Eigen::Vector3d& size,
                      PenetrationPolicy policy = PenetrationPolicy::Refuse);
  Status set_cylinder_size(ObjectId id, int component, double radius, double height,
                           PenetrationPolicy policy = PenetrationPolicy::Refuse);
  Status set_sphere_size(ObjectId id, int component, double radius,
                         PenetrationPolicy policy = PenetrationPolicy::Refuse);
  /// A ramp's width, height and angle (depth follows: height / tan angle).
  Status set_ramp(ObjectId id, const RampGeometry& ramp,
                  PenetrationPolicy policy = PenetrationPolicy::Refuse);
  /// Colour of one component, or of all (component -1).
  Status set_color(ObjectId id, const Color& color, int component = -1);
  /// Texture of one component, or of all (component -1); empty path removes it.
  Status set_texture(ObjectId id, const std::string& path, int component = -1);
  /// Mass (kg); the density follows, mass and inertia are recomputed exactly.
  Status set_mass(ObjectId id, double mass);
  /// Density (kg/m^3); the mass follows, mass and inertia are recomputed exactly.
  Status set_density(ObjectId id, double density);
  Status set_linear_velocity(ObjectId id, const Eigen::Vector3d& velocity);
  Status set_angular_velocity(ObjectId id, const Eigen::Vector3d& velocity);
  /// A force (N, world frame, at the centre of mass) acting during the next step only.
  Status add_force(ObjectId id, const Eigen::Vector3d& force);
  /// A torque (N m, world frame) acting during the next step only.
  Status add_torque(ObjectId id, const Eigen::Vector3d& torque);
  /// Frozen objects stay where they are (others still collide with them).
  Status set_frozen(ObjectId id, bool frozen);
  Status set_magnetizable(ObjectId id, bool magnetizable);
  Status set_user_data(ObjectId id, const std::string& user_data);
  /// User-defined colour and shape labels (need not match the object's looks).
  Status set_user_labels(ObjectId id, int user_color, int user_shape);

  /// Objects the world may hold at most (created and imported ones included): an operation that
  /// would pass it is refused with LimitReached. Default bounds::kMaxObjects (macsim
  /// --max-objects).
  void set_max_objects(std::size_t max_objects) { max_objects_ = max_objects; }
  std::size_t max_objects() const { return max_objects_; }

 private:
  /// Checks a new object's description (cap, kind, bounds, textures, material, name) and puts
  /// it in its one form (a ramp's box, normalised orientations, textures in one spelling).
  Status validate_new_object(ObjectSpec& spec) const;
  /// Adds a loaded fragment's objects, joints and doors; their ids go to `ids`.
  Status add_spec_objects(WorldSpec fragment, std::vector<ObjectId>* ids);
  /// Removes an object and the joints that hold it (its door's record stays).
  void erase_object(ObjectId id);
  int destroy_matching(const std::function<bool(const ObjectSpec&)>& match);
  /// Rebuilds an object from `spec` at `state`, re-attaching its joints where they were.
  void rebuild_object(detail::ObjectRecord& object, const ObjectSpec& spec,
                      const ObjectState& state);
  /// Runs `change` on a copy of the object's description and rebuilds; refuses (restoring the
  /// old description and pose) when it penetrates and the policy says so.
  Status change_object(ObjectId id, PenetrationPolicy policy,
                       const std::function<Status(ObjectSpec&, Pose&)>& change);
  Status resize_component(ObjectId id, int component, Shape shape, const Eigen::Vector3d& size,
                          PenetrationPolicy policy);
  /// BadTexture for a file that is no usable texture, BadFile for one the roots refuse.
  Status texture_status(const std::string& path) const;
  /// The free body of `id`, woken, if `value` is within the bounds of `what`.
  Status dynamic_body(ObjectId id, const Eigen::Vector3d& value, const char* what,
                      dxBody*& body) const;

  detail::ObjectTable& table_;
  detail::DoorTable& doors_;
  detail::WorldPhysics& physics_;
  std::size_t max_objects_ = bounds::kMaxObjects;
};

/// The world's door-switch structures: read, triggered, moved (World::doors()).
class WorldDoors {
 public:
  /// A view of the world's door table, moving their parts through `physics` (World makes it).
  WorldDoors(detail::DoorTable& doors, detail::ObjectTable& objects, detail::WorldPhysics& physics)
      : doors_(doors), objects_(objects), physics_(physics) {}
  WorldDoors(const WorldDoors&) = delete;
  WorldDoors& operator=(const WorldDoors&) = delete;

  /// How many door-switch structures the world holds.
  int door_count() const;
  /// The index of the door of that name, or nothing.
  std::optional<int> find_door(const std::string& name) const;
  /// The index of the door of that name, or UnknownObject naming the name.
  Result<int> get_door_by_name(const std::string& name) const;
  Result<DoorState> door_state(int door) const;
  Result<DoorParts> door_parts(int door) const;
  const std::string& door_name(int door) const;
  /// Presses the switch virtually (the door opens) or hands it back to physics.
  Status set_switch_triggered(int door, bool triggered);
  /// Moves the door's leaf there (position of the leaf's frame); the frame moves along.
  Status set_door_position(int door, const Eigen::Vector3d& position);
  /// Moves the switch's platform there; the base moves along.
  Status set_switch_position(int door, const Eigen::Vector3d& position);

 private:
  Status check_door(int door) const;
  /// Moves the leaf (or the switch's platform) with its fixed part and their joint.
  Status move_door_part(int door, bool leaf, const Eigen::Vector3d& position);

  detail::DoorTable& doors_;
  detail::ObjectTable& objects_;
  detail::WorldPhysics& physics_;
};

/// The ODE world of one simulation.
class World {
 public:
  /// Builds the world; throws WorldFileError (with the spec's file and line) on what cannot be
  /// built: an unknown robot type, a magnitude out of bounds (world_bounds.h). Seeds ODE's random
  /// generator for determinism.
  explicit World(WorldSpec spec);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // ---- stepping ------------------------------------------------------------------------
  /// Advances one fixed step: doors and robots' motors, collisions, QuickStep, encoders,
  /// instability check (a body gone NaN or wild is put back and reported). False when a body
  /// went unstable or ODE reported an error (then this world steps no more).
  bool step();
  /// Robot drive commands still in force are renewed now (a controller stepping the world
  /// through a long request keeps its robot moving): those of the robots named, comma-separated
  /// (robot names have no commas), or of every robot when `robots` is empty.
  void keep_robot_commands(const std::string& robots = "");
  double time() const { return static_cast<double>(steps_) * spec_.physics.step; }
  uint64_t steps() const { return steps_; }
  /// The step its time was last set to, and how often it was set: sensor schedules begin anew
  /// at each (a resumed run, replaying the same resets and restores, keeps them).
  struct TimeOrigin {
    uint64_t step = 0;   ///< 0 as loaded or reset, a restored snapshot's step
    uint64_t count = 0;  ///< resets (of the time) and restores since the world was loaded
  };
  TimeOrigin time_origin() const { return time_origin_; }
  double step_size() const { return spec_.physics.step; }
  /// The world as loaded.
  const WorldSpec& spec() const { return spec_; }
  /// Contact points created in the last step.
  int contact_count() const { return contacts_; }
  /// Where the steps' wall time went since the world was built (or its profile was cleared).
  struct StepProfile {
    std::uint64_t steps = 0;
    double collision = 0.0;  ///< s: pairs found and contacts made
    double solver = 0.0;     ///< s: ODE's step (islands, QuickStep, integration)
    double robots = 0.0;     ///< s: the robots' work before and after it (drive, sensors)
    double other = 0.0;      ///< s: stability check, doors, events
  };
  const StepProfile& step_profile() const { return profile_; }
  void clear_step_profile() { profile_ = {}; }

  // ---- robots --------------------------------------------------------------------------
  /// The robot of that name, or nullptr.
  RobotModel* robot(const std::string& name);
  /// The robot of that name if it is a T (e.g. KurtRobot), or nullptr.
  template <class T>
  T* robot_as(const std::string& name) {
    return dynamic_cast<T*>(robot(name));
  }
  const std::vector<std::unique_ptr<RobotModel>>& robots() const { return robots_; }

  // ---- objects and doors -----------------------------------------------------------------
  /// Finding and reading objects.
  const WorldObjects& objects() const { return objects_view_; }
  /// Creating, destroying and changing objects.
  WorldEditor& edit() { return editor_; }
  /// The door-switch structures.
  WorldDoors& doors() { return doors_view_; }
  const WorldDoors& doors() const { return doors_view_; }

  /// Every object's and robot's shapes as they stand now, with their looks (for renderers).
  std::vector<ShapeView> shapes() const;
  /// Pairs of objects and robots (or one of them and the ground) inside each other deeper than
  /// `tolerance` (m) as they stand now; right after loading: as they start. Not overlaps: parts
  /// of one object, one door-switch structure or one robot; bodies joined by a joint; things that
  /// cannot move (fixed objects, frozen ones, the ground) among themselves; a ramp in the ground.
  /// One collision pass over ODE's space: about the cost of a step's collisions.
  OverlapReport overlaps(double tolerance = kOverlapTolerance) const;

  // ---- events, state, reset ------------------------------------------------------------
  /// Events since the last call.
  std::vector<WorldEvent> take_events();
  /// The complete state, by part.
  WorldState state() const;
  /// The complete state, serialised and marked with this world's fingerprint.
  WorldSnapshot snapshot() const;
  /// Puts the world back to a snapshot of this world (another world's, or damaged bytes, are
  /// refused and change nothing): description, time, ids, random state, every body (orientations
  /// to within ODE's quaternion renormalization, about 1e-16), doors and robots.
  Status restore(const WorldSnapshot& snapshot);
  /// Resets the scope; a reset of everything (or of poses and time, when nothing was spawned)
  /// is bit-identical to loading the world afresh.
  void reset(ResetScope scope);
  /// Hash of the complete state (macsim::state_hash(state())): equal states, equal hashes.
  uint64_t state_hash() const;
  /// Identifies the world as loaded (its description and initial state); snapshots carry it.
  uint64_t fingerprint() const { return fingerprint_; }

  // ---- files ---------------------------------------------------------------------------
  /// Where the operations that name files (textures, imports) may read them; nullptr: anywhere.
  void set_data_roots(std::shared_ptr<const DataRoots> roots);
  const DataRoots& data_roots() const { return *files_; }

 private:
  using Object = detail::ObjectRecord;
  using Joint = detail::JointRecord;
  /// World as what its parts ask of ODE (detail::WorldPhysics), in world.cpp.
  struct Physics;

  /// Builds ODE from the records, the bodies in `body_order` (WorldState::body_order).
  void build(const std::vector<int64_t>& body_order = {});
  /// Builds the robot of that index in the spec.
  void build_robot_at(std::size_t index);
  /// A robot's token in body_order_, and back.
  static int64_t robot_token(std::size_t index) { return -1 - static_cast<int64_t>(index); }
  static std::size_t robot_of_token(int64_t token) { return static_cast<std::size_t>(-1 - token); }
  /// Rebuilds ODE from a snapshot's description; bodies of `fresh` objects (and the robots,
  /// if `fresh_robots`) stay as built, at rest at their reference poses.
  void rebuild(const WorldState& state, const std::vector<ObjectId>& fresh, bool fresh_robots);
  void refresh_bodies();
  uint64_t world_fingerprint() const;
  /// After a supervisor change: refresh the body list and wake every sleeping body.
  void structure_changed();
  /// Wakes a body: it counts its still steps anew (ODE's dBodyEnable, and the count).
  void wake(dxBody* body);
  /// Puts to sleep the bodies that may sleep, touch something and stayed still for
  /// kStillStepsToSleep steps (ODE's own rule, ODE's auto-disable off); how many are awake.
  std::size_t sleep_still_bodies();
  void clear_ode();
  /// Makes an object's body (or takes the one kept for it) and geoms.
  void build_object(Object& object);
  /// Destroys an object's geoms and body; `keep_body`: the body stays for build_object to take
  /// again, keeping its place in ODE's order (an object changed in place).
  void destroy_ode_object(Object& object, bool keep_body = false);
  void build_joint(Joint& joint);
  std::vector<std::string> penetrations(const Object& object) const;
  bool check_stability();  // false if a body had to be put back
  void emit(WorldEvent::Type type, const std::string& subject, const std::string& detail = "");
  static void near_callback(void* data, dxGeom* a, dxGeom* b);
  std::vector<dxGeom*> collision_order() const;

  WorldSpec spec_;  // as loaded
  dxWorld* world_ = nullptr;
  dxSpace* space_ = nullptr;
  std::unique_ptr<detail::BroadPhase> broad_phase_;
  bool geoms_changed_ = true;  // the broad phase must take the geoms anew before a step
  dxJointGroup* contact_group_ = nullptr;
  void* threading_ = nullptr;
  dxGeom* ground_ = nullptr;
  std::unique_ptr<detail::GeomTag> ground_tag_;
  std::unique_ptr<detail::ObjectTable> table_;  // the objects and joints
  std::unique_ptr<Physics> physics_;
  std::unique_ptr<detail::DoorTable> door_table_;
  std::vector<std::unique_ptr<RobotModel>> robots_;
  std::vector<std::unique_ptr<detail::GeomTag>> robot_tags_;  // for geoms a robot left untagged
  std::vector<dxBody*> bodies_;                               // every body, for the stability check
  std::vector<std::string> body_names_;                       // owner of each body, for reports
  std::vector<BodyState> last_good_;
  // Sleep, decided here so that it is part of the state: per body, whether it may sleep and
  // the still steps it has left.
  static constexpr int32_t kStillStepsToSleep = 50;
  std::vector<uint8_t> may_sleep_;
  std::vector<int32_t> still_steps_left_;
  std::unordered_map<dxBody*, std::size_t> body_index_;
  std::vector<int64_t> body_order_;  // the order the bodies were made in (WorldState::body_order)
  std::string fault_;                // ODE's error inside a step: the world steps no more
  std::vector<WorldEvent> events_;
  std::shared_ptr<const DataRoots> files_ = DataRoots::anywhere();
  WorldState initial_;
  uint64_t fingerprint_ = 0;
  unsigned long random_seed_ = 0;  // this world's dRand state
  uint64_t steps_ = 0;
  TimeOrigin time_origin_;
  int contacts_ = 0;
  StepProfile profile_;
  WorldObjects objects_view_;
  WorldEditor editor_;
  WorldDoors doors_view_;
};

}  // namespace macsim
