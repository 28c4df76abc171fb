// The bounds every magnitude of a world keeps, checked in one place: the loader (a world or an
// environment file, once parsed), the World's constructor (a spec built in code) and the
// supervisor (each request) call the same checks, so what a file may hold and what a request
// may set agree, and nothing out of bounds reaches ODE. SI units.
#pragma once

#include <optional>
#include <string>

#include "macsim/sim_core/world_spec.h"

namespace macsim::bounds {

inline constexpr double kMaxCoordinate = 1e4;  ///< m: |x|, |y|, |z| of any position
inline constexpr double kMinSize = 1e-4;       ///< m: a box side, a radius, a height
inline constexpr double kMaxSize = 1e3;        ///< m
inline constexpr double kMinDensity = 1.0;     ///< kg/m^3
inline constexpr double kMaxDensity = 1e5;     ///< kg/m^3 (osmium: 2.26e4)
inline constexpr double kMinMass = 1e-5;       ///< kg, of a portable object
inline constexpr double kMaxMass = 1e6;        ///< kg, of a portable object
inline constexpr double kMinStep = 1e-6;       ///< s
inline constexpr double kMaxStep = 0.1;        ///< s
inline constexpr int kMaxSolverIterations = 1000;
inline constexpr double kMaxGravity = 1e3;       ///< m/s^2
inline constexpr double kMaxFriction = 1e3;      ///< Coulomb mu
inline constexpr double kMaxSpeed = 1e3;         ///< m/s, set or driven
inline constexpr double kMaxAngularSpeed = 1e4;  ///< rad/s
inline constexpr double kMaxForce = 1e6;         ///< N (and N m for torques)
inline constexpr double kMaxEncoderRate = 1e4;   ///< Hz
inline constexpr std::size_t kMaxNameLength = 256;
// The defaults of LoadLimits (world_loader.h), which a load may raise or lower:
inline constexpr std::size_t kMaxImportDepth = 32;       ///< <IMPORT>s nested in one another
inline constexpr std::size_t kMaxImportedFiles = 10000;  ///< imports read for one world in all
inline constexpr std::size_t kMaxObjects = 100000;       ///< objects of one world

/// Why a name is unusable, or nothing: segments of letters, digits, `_`, `-` and `.` (not `.`
/// or `..`) joined by `/`, at most kMaxNameLength characters in all.
std::optional<std::string> name_problem(const std::string& name);
/// The same for one segment (an <ID> in a file): no `/`.
std::optional<std::string> id_problem(const std::string& id);
/// A position within kMaxCoordinate in every axis, finite.
std::optional<std::string> position_problem(const Eigen::Vector3d& position);
/// A finite quaternion that can be normalized.
std::optional<std::string> orientation_problem(const Eigen::Quaterniond& orientation);
/// A finite vector of norm at most `max` (`what` names it in the message).
std::optional<std::string> magnitude_problem(const Eigen::Vector3d& v, double max,
                                             const char* what);
/// An object's pose, components (shape sizes, offsets, colours), density, derived mass (when
/// portable) and ramp geometry.
std::optional<std::string> object_problem(const ObjectSpec& object);
std::optional<std::string> physics_problem(const PhysicsSpec& physics);
std::optional<std::string> material_problem(const MaterialSpec& material);
/// Its axis, anchor, stops, motor, and two different bodies.
std::optional<std::string> joint_problem(const JointSpec& joint);
std::optional<std::string> robot_problem(const RobotSpec& robot);
/// Every part of a world; throws WorldFileError naming the element's file and line.
void check_world(const WorldSpec& world);

}  // namespace macsim::bounds
