// World's parts inside sim_core: the records of what ODE holds, the tables that own them (the
// objects and joints, the doors), and what the parts ask of the ODE world (WorldPhysics).
#pragma once

#include <ode/ode.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "macsim/sim_core/world.h"
#include "ode_support.h"

namespace macsim {

namespace detail {

/// An object as ODE holds it, beside its current description.
struct ObjectRecord {
  ObjectId id = 0;
  ObjectSpec spec;  // pose: where it was placed (for jointed bodies: the joint's zero)
  dBodyID body = nullptr;
  std::vector<dGeomID> geoms;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();  // centre of mass in the object's frame
  detail::GeomTag tag;
  int door = -1;  // index of the door it belongs to, -1 if none
};

/// A joint and, while it is being rebuilt, the position it had.
struct JointRecord {
  JointSpec spec;
  dJointID joint = nullptr;
  double position = 0.0;  // slider m / hinge rad, kept across a rebuild
};

/// A door-switch structure and its runtime state.
struct DoorRecord {
  DoorSpec spec;
  JointRecord* door_joint = nullptr;
  JointRecord* switch_joint = nullptr;
  DoorFlags flags;
};

/// The world's objects, in list order (the seed's indices), with their ids, and the joints
/// between them: the one owner of their records.
class ObjectTable {
 public:
  /// The one factory of an object's record.
  ObjectRecord& add(ObjectId id, ObjectSpec spec);
  /// The one factory of a joint's record.
  JointRecord& add_joint(JointSpec spec);
  /// The next object's id, taken: ids are never reused while the world lives.
  ObjectId take_id() { return next_id_++; }
  ObjectId next_id() const { return next_id_; }
  /// Sets the next id (a refused creation gives its id back; a restore sets the saved one).
  void set_next_id(ObjectId id) { next_id_ = id; }

  ObjectRecord* find(ObjectId id) const;
  /// The object of that name, or nullptr.
  ObjectRecord* find_named(const std::string& name) const;
  /// The object `id` in `out`, or UnknownObject naming the id.
  Status check(ObjectId id, const ObjectRecord*& out) const;
  std::optional<int> index_of(ObjectId id) const;
  JointRecord* joint_named(const std::string& name) const;

  /// Forgets an object's record (its ODE parts destroyed already).
  void erase(ObjectId id);
  /// Forgets a joint's record (its ODE joint destroyed already).
  void erase_joint(const JointRecord* joint);
  /// Forgets every object and joint (their ODE parts destroyed already).
  void clear();

  std::size_t size() const { return objects_.size(); }
  const std::vector<std::unique_ptr<ObjectRecord>>& objects() const { return objects_; }
  const std::vector<std::unique_ptr<JointRecord>>& joints() const { return joints_; }

 private:
  std::vector<std::unique_ptr<ObjectRecord>> objects_;
  std::vector<std::unique_ptr<JointRecord>> joints_;
  ObjectId next_id_ = 1;
};

/// What World's parts ask of the ODE world that holds their records (World implements it).
class WorldPhysics {
 public:
  /// Makes an object's body (or takes the one kept for it) and geoms.
  virtual void build_object(ObjectRecord& object) = 0;
  /// Destroys an object's geoms and body; `keep_body`: the body stays for build_object to take
  /// again, keeping its place in ODE's order (an object changed in place).
  virtual void destroy_object(ObjectRecord& object, bool keep_body = false) = 0;
  /// Attaches a joint anew where its bodies are (keeping the position it had).
  virtual void build_joint(JointRecord& joint) = 0;
  /// After a change: the body list refreshed and every sleeping body woken.
  virtual void structure_changed() = 0;
  /// Wakes a body: it counts its still steps anew.
  virtual void wake(dBodyID body) = 0;
  /// The objects and robots (or "ground") the object lies inside, as it stands now.
  virtual std::vector<std::string> penetrations(const ObjectRecord& object) const = 0;
  virtual void emit(WorldEvent::Type type, const std::string& subject,
                    const std::string& detail = "") = 0;
  /// The world's material of that name, or nullptr (WorldSpec::material).
  virtual const MaterialSpec* material(const std::string& name) const = 0;
  /// The world's materials (an environment added brings its own).
  virtual std::vector<MaterialSpec>& materials() = 0;
  /// Where the operations that name files may read them.
  virtual const DataRoots& data_roots() const = 0;

 protected:
  ~WorldPhysics() = default;
};

/// The world's door-switch structures: the one owner of their records, tied to the joints and
/// objects they are made of, driven at each step.
class DoorTable {
 public:
  DoorTable(ObjectTable& objects, WorldPhysics& physics) : objects_(objects), physics_(physics) {}
  /// A door's record; wire() ties it to its joints and objects.
  void add(DoorSpec spec, DoorFlags flags);
  /// Forgets a door (its objects destroyed already) and ties the rest anew.
  void remove(int door);
  void clear() { doors_.clear(); }
  /// Ties each door to its joints and marks its objects as its parts.
  void wire();
  /// Before a step: each door driven open or shut by its switch; events when a switch changes.
  void before_step();
  /// After a step: events for the doors that came fully open or shut.
  void after_step();
  static DoorState state_of(const DoorRecord& door);
  /// The objects door `door` is made of.
  DoorParts parts(int door) const;
  const std::vector<std::unique_ptr<DoorRecord>>& doors() const { return doors_; }

 private:
  ObjectTable& objects_;
  WorldPhysics& physics_;
  std::vector<std::unique_ptr<DoorRecord>> doors_;
};

/// An object's pose and velocities as ODE holds them (its placed pose when it has no body).
ObjectState object_state(const ObjectRecord& object);
/// Ok if the object is a free rigid body (WorldObjects::free_body).
Status free_body(const ObjectRecord& object, const std::string& what);

/// InvalidArgument with that message.
inline Status invalid_argument(const std::string& message) {
  return Status::error(ErrorCode::InvalidArgument, message);
}

/// Pose of a body's centre of mass and its velocities.
BodyState body_state(dBodyID body);
void set_body_state(dBodyID body, const BodyState& state);
/// True if every number of the state is finite and the speeds are physically plausible.
bool plausible(const BodyState& state);
/// How deep a point lies inside a geom (negative: outside). ODE's colliders miss some deep,
/// concentric overlaps (a box centred in a cylinder gives no contact); this catches them.
double point_depth(dGeomID g, const dReal* p);
}  // namespace detail

}  // namespace macsim
