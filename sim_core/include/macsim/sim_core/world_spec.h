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
};

/// Where a spec element was written, for error messages.
struct SourceLocation {
  std::string file;
  int line = 0;
};

/// Global physics settings of a world.
struct PhysicsSpec {
  double step = 0.001;                           ///< s, fixed step
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};      ///< m/s^2
  int solver_iterations = 50;                    ///< ODE QuickStep iterations
  double erp = 0.2;                              ///< error reduction parameter
  double cfm = 1e-5;                             ///< constraint force mixing
  uint32_t seed = 1;                             ///< ODE random seed (QuickStep reordering)
};

/// Collision shapes of the seed: box, cylinder (axis along local z) and sphere.
enum class Shape { Box, Cylinder, Sphere };

/// One primitive object: fixed (geometry only) or portable (a rigid body).
struct ObjectSpec {
  std::string id;                     ///< unique within the world
  bool portable = true;
  Shape shape = Shape::Box;
  Eigen::Vector3d size = Eigen::Vector3d::Constant(0.1);  ///< box: x,y,z; cylinder: r,-,h; sphere: r
  Pose pose;
  double density = 100.0;             ///< kg/m^3 (seed default 0.1 kg/L)
  std::optional<double> mass;         ///< kg; overrides density when given
  std::array<float, 4> color{0.5f, 0.5f, 0.5f, 1.0f};  ///< RGBA in [0,1] (seed default gray)
  double friction = 1.0;              ///< Coulomb mu
  std::string user_data;
  SourceLocation source;
};

/// One robot instance of a registered robot type (e.g. "kurt3d").
struct RobotSpec {
  std::string name;  ///< namespace of its topics, e.g. "kurt"
  std::string type;  ///< robot type name
  Pose pose;         ///< pose of base_footprint (on the floor)
  SourceLocation source;
};

/// A whole world: physics settings, a ground plane, objects and robots.
struct WorldSpec {
  std::string name;
  std::string file;  ///< the world file it was loaded from (empty if built in code)
  PhysicsSpec physics;
  bool ground = true;           ///< infinite plane z = 0
  double ground_friction = 1.0;
  std::vector<ObjectSpec> objects;
  std::vector<RobotSpec> robots;
};

}  // namespace macsim
