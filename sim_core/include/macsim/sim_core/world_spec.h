// What a world *is*: the description loaded from XML, independent of ODE and of time.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace macsim {

/// A rigid transform: position in m, orientation as a unit quaternion (z up, REP-103).
struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();

  /// This pose applied after `inner`: the pose of a child given in this frame.
  Pose operator*(const Pose& inner) const {
    return {position + orientation * inner.position, orientation * inner.orientation};
  }
  /// The inverse transform.
  Pose inverse() const {
    const Eigen::Quaterniond q = orientation.conjugate();
    return {q * -position, q};
  }
};

/// Where a spec element was written, for error messages.
struct SourceLocation {
  std::string file;
  int line = 0;
};

/// RGBA colour, each channel in [0, 1].
using Color = std::array<float, 4>;

/// Global physics settings of a world.
struct PhysicsSpec {
  double step = 0.001;                       ///< s, fixed step
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  ///< m/s^2
  int solver_iterations = 25;                ///< ODE QuickStep iterations
  double erp = 0.2;                          ///< error reduction parameter
  double cfm = 1e-5;                         ///< constraint force mixing
  uint32_t seed = 1;                         ///< ODE random seed (QuickStep reordering)
  SourceLocation source;                     ///< the <PHYSICS> element, if any
};

/// A named surface: friction, restitution and a default density for objects made of it.
struct MaterialSpec {
  std::string name;
  double friction = 1.0;         ///< Coulomb mu; a contact uses the geometric mean of both
  double bounce = 0.0;           ///< restitution in [0, 1]; a contact uses the larger
  double bounce_velocity = 0.1;  ///< m/s, slower impacts do not bounce
  double density = 100.0;        ///< kg/m^3, default for objects of this material
  SourceLocation source;
};

/// Collision shapes of the seed: box, cylinder (axis along local z) and sphere.
enum class Shape { Box, Cylinder, Sphere };

/// Name of a shape as written in world files ("BOX", ...).
const char* shape_name(Shape shape);

/// One geometry of an object, placed relative to the object's frame.
struct ComponentSpec {
  Shape shape = Shape::Box;
  /// Box: full sizes x, y, z. Cylinder: radius, unused, height. Sphere: radius, unused, unused.
  Eigen::Vector3d size = Eigen::Vector3d::Constant(0.1);
  Pose pose;                            ///< relative to the object's frame
  Color color{0.5f, 0.5f, 0.5f, 1.0f};  ///< seed default: gray
  std::string texture;                  ///< BMP path (resolved), empty for none
};

/// A shape as it stands in the world right now, with its looks: what a renderer draws.
struct ShapeView {
  Shape shape = Shape::Box;
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< as ComponentSpec::size
  Pose pose;                                       ///< of the shape's centre, world frame
  Color color{0.5f, 0.5f, 0.5f, 1.0f};
  std::string texture;
};

/// Volume of one component in m^3.
double component_volume(const ComponentSpec& component);

/// What role an object plays; all of them are objects the supervisor can reach.
enum class ObjectKind {
  Object,          ///< a basic (one component) or composite object
  Wall,            ///< a fixed box standing on the floor
  Ramp,            ///< a box rotated and embedded in the ground
  SwitchBase,      ///< the fixed base of a door switch
  SwitchPlatform,  ///< the moving platform of a door switch
  DoorFrame,       ///< the fixed part of a door
  DoorLeaf,        ///< the moving (sliding or swinging) part of a door
};

/// A ramp described as the seed does: width plus height (or depth) and slope angle.
struct RampGeometry {
  double width = 1.0;   ///< m, across the slope
  double height = 0.1;  ///< m, of the top edge above the floor
  double angle = 0.2;   ///< rad, slope
  /// A ramp given by width, horizontal run and angle (the seed's WidthDepthAngle).
  static RampGeometry from_depth(double width, double depth, double angle);
  /// Horizontal run from the foot to the top edge: height / tan(angle).
  double depth() const;
  /// Length of the sloped surface.
  double length() const;
  /// The embedded box: its sizes and its pose relative to the ramp's foot frame.
  ComponentSpec box() const;
};

/// One object: basic (one component) or composite (several on one rigid body).
struct ObjectSpec {
  std::string name;  ///< unique path, e.g. "doors/door_00/switch_component/base"
  ObjectKind kind = ObjectKind::Object;
  bool portable = true;  ///< portable: a rigid body; fixed: geometry only
  std::vector<ComponentSpec> components;
  Pose pose;               ///< of the object's frame in the world
  double density = 100.0;  ///< kg/m^3 (seed default 0.1 kg/L); mass = density * volume
  std::string material = "default";
  bool magnetizable = false;         ///< the crane's magnet can hold it
  bool frozen = false;               ///< held in place (kinematic) although portable
  std::string user_data;             ///< free text; objects can be looked up by it
  int user_color = 0;                ///< user-defined colour label (need not match the colour)
  int user_shape = 0;                ///< user-defined shape label (need not match the shape)
  std::optional<RampGeometry> ramp;  ///< set for ramps: the component is derived from it
  SourceLocation source;

  /// Total volume of the components (overlaps count twice, as ODE's mass sum does).
  double volume() const;
  /// density * volume, in kg.
  double mass() const { return density * volume(); }
};

/// Makes the object's and its components' quaternions unit length (they must be non-zero).
void normalize_orientations(ObjectSpec& object);

/// A box object (the seed's create{Box}{Portable,Fixed}Object), centred at `position`.
ObjectSpec box_object(const Eigen::Vector3d& position, const Eigen::Vector3d& size,
                      bool portable = true, const std::string& user_data = "");
/// A cylinder object (axis along z), centred at `position`.
ObjectSpec cylinder_object(const Eigen::Vector3d& position, double radius, double height,
                           bool portable = true, const std::string& user_data = "");
/// A sphere object, centred at `position`.
ObjectSpec sphere_object(const Eigen::Vector3d& position, double radius, bool portable = true,
                         const std::string& user_data = "");

/// Radius (m) of an object's footprint on the floor about its frame's vertical axis.
double footprint_radius(const ObjectSpec& object);

/// A joint between two objects (or an object and the world), e.g. a switch's slider.
struct JointSpec {
  enum class Type { Slider, Hinge };
  std::string name;  ///< unique path, like object names
  Type type = Type::Slider;
  std::string body1;                ///< the moving object's name
  std::string body2;                ///< the other object's name; empty or fixed: the world
  Eigen::Vector3d axis{0, 0, 1};    ///< in the world frame
  Eigen::Vector3d anchor{0, 0, 0};  ///< hinge anchor, world frame
  double lo = 0.0, hi = 0.0;        ///< stops: m (slider) or rad (hinge)
  double max_force = 0.0;           ///< motor force (N) or torque (N m); 0: no motor
  double velocity = 0.0;            ///< motor set-point, m/s or rad/s
  SourceLocation source;
};

/// A door-switch structure (the seed's door_%02d): an automatic door opened while its switch
/// is pressed fully (or triggered virtually). Parts refer to objects and joints by name.
struct DoorSpec {
  std::string name;                                        ///< e.g. "door_00"
  std::string switch_base, switch_platform, switch_joint;  ///< empty when it has no switch
  std::string frame, leaf, door_joint;
  SourceLocation source;
};

/// One robot instance of a registered robot type (e.g. "kurt3d").
struct RobotSpec {
  std::string name;             ///< namespace of its topics, e.g. "kurt"
  std::string type;             ///< robot type name
  Pose pose;                    ///< pose of base_footprint (on the floor)
  double encoder_rate = 100.0;  ///< Hz of encoder frames (odometry, IR/sonar, gyro); real: 100
  SourceLocation source;
};

/// A joint's motor force drawn per seed (a switch's stiffness), within [lo, hi].
struct JointForceRange {
  std::string joint;      ///< the joints whose names end with this id (e.g. "BUTTON_SLIDER")
  double lo = 0, hi = 0;  ///< N (slider) or N m (hinge)
  SourceLocation source;
};

/// More objects placed per seed in an area of their own (<VARIATION>'s <PLACE>), after
/// everything else: clutter across a way, beside the cans of the main area.
struct PlaceGroup {
  std::string user_data;             ///< the objects placed are those with this user data
  Eigen::Vector4d area{0, 0, 0, 0};  ///< x_min, y_min, x_max, y_max on the floor, m
  bool inside = false;               ///< whole footprints in `area`, not only centres
  double clearance = 0.1;            ///< m between their footprints and everything placed or standing
  SourceLocation source;
};

/// How a world varies with a seed (the <VARIATION> element; `macsim --seed N`): objects placed
/// at random in an area, one colour per material drawn from a palette, the robots' start, joint
/// motor forces drawn from ranges.
struct VariationSpec {
  std::string user_data;                      ///< the objects placed are those with this user data
  Eigen::Vector4d area{0, 0, 0, 0};           ///< x_min, y_min, x_max, y_max on the floor, m
  std::optional<Eigen::Vector4d> robot_area;  ///< where the robots start (any heading)
  bool inside = false;  ///< the placed objects' whole footprints lie in `area`, not only centres
  double clearance = 0.45;                    ///< m between footprints of placed objects and others
  std::vector<Color> colors;                  ///< palette for the first component of placed objects
  std::vector<std::string> keep_colors;       ///< materials whose objects keep their own colour
  std::vector<JointForceRange> joint_forces;  ///< motor forces drawn per seed
  std::vector<PlaceGroup> groups;             ///< placed after the joint forces, in order
  SourceLocation source;
};

/// A whole world: physics settings, ground plane, materials, objects, joints, doors, robots.
struct WorldSpec {
  std::string name;
  std::string file;  ///< the world file it was loaded from (empty if built in code)
  PhysicsSpec physics;
  double ground_friction = 1.0;         ///< the plane z = 0
  std::vector<MaterialSpec> materials;  ///< always holds "default"
  std::vector<ObjectSpec> objects;
  std::vector<JointSpec> joints;
  std::vector<DoorSpec> doors;
  std::vector<RobotSpec> robots;
  std::optional<VariationSpec> variation;  ///< how --seed varies it, if it says

  /// The material of that name, or nullptr.
  const MaterialSpec* material(const std::string& material_name) const;
  /// The object of that name, or nullptr.
  const ObjectSpec* object(const std::string& object_name) const;
};

}  // namespace macsim
