#include "macsim/sim_core/world_bounds.h"

#include <cmath>
#include <cstdio>

#include "macsim/sim_core/robot_model.h"
#include "macsim/sim_core/world_loader.h"

namespace macsim::bounds {

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

std::string vector(const Eigen::Vector3d& v) {
  return "(" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + ")";
}

bool within(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

std::optional<std::string> size_problem(double v, const char* what) {
  if (within(v, kMinSize, kMaxSize)) return std::nullopt;
  return std::string(what) + " must lie in [" + number(kMinSize) + ", " + number(kMaxSize) +
         "] m, got " + number(v);
}

std::optional<std::string> component_problem(const ComponentSpec& c) {
  switch (c.shape) {
    case Shape::Box:
      for (int i = 0; i < 3; ++i) {
        if (auto p = size_problem(c.size[i], "a box side")) return p;
      }
      break;
    case Shape::Cylinder:
      if (auto p = size_problem(c.size.x(), "a cylinder's radius")) return p;
      if (auto p = size_problem(c.size.z(), "a cylinder's height")) return p;
      break;
    case Shape::Sphere:
      if (auto p = size_problem(c.size.x(), "a sphere's radius")) return p;
      break;
    default:
      return "unknown shape code " + std::to_string(static_cast<int>(c.shape));
  }
  if (!c.pose.position.allFinite() || c.pose.position.cwiseAbs().maxCoeff() > kMaxSize) {
    return "a component's offset must lie within " + number(kMaxSize) + " m of its object, got " +
           vector(c.pose.position);
  }
  if (auto p = orientation_problem(c.pose.orientation)) return "a component's " + *p;
  for (float channel : c.color) {
    if (!within(channel, 0.0, 1.0)) return std::string("colour channels must lie in [0, 1]");
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> id_problem(const std::string& id) {
  if (id.empty()) return std::string("a name must not be empty");
  if (id.size() > kMaxNameLength) {
    return "a name may have at most " + std::to_string(kMaxNameLength) + " characters";
  }
  if (id == "." || id == "..") return "'" + id + "' is not a name";
  for (unsigned char c : id) {
    if (!std::isalnum(c) && c != '_' && c != '-' && c != '.') {
      return "'" + id + "' may hold only letters, digits, _ - and .";
    }
  }
  return std::nullopt;
}

std::optional<std::string> name_problem(const std::string& name) {
  if (name.size() > kMaxNameLength) {
    return "a name may have at most " + std::to_string(kMaxNameLength) + " characters";
  }
  std::size_t start = 0;
  for (;;) {
    const std::size_t slash = name.find('/', start);
    const std::string segment = name.substr(start, slash - start);
    if (auto p = id_problem(segment)) {
      return "'" + name + "' is not a name: segments of letters, digits, _ - and . joined by /";
    }
    if (slash == std::string::npos) return std::nullopt;
    start = slash + 1;
  }
}

std::optional<std::string> position_problem(const Eigen::Vector3d& p) {
  if (p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxCoordinate) return std::nullopt;
  return "a position must be finite and within " + number(kMaxCoordinate) +
         " m of the origin in every axis, got " + vector(p);
}

std::optional<std::string> orientation_problem(const Eigen::Quaterniond& q) {
  const double norm = q.norm();
  if (q.coeffs().allFinite() && std::isfinite(norm) && norm > 1e-9) return std::nullopt;
  return std::string("orientation must be a finite, non-zero quaternion");
}

std::optional<std::string> magnitude_problem(const Eigen::Vector3d& v, double max,
                                             const char* what) {
  if (v.allFinite() && v.norm() <= max) return std::nullopt;
  return std::string(what) + " must be finite and at most " + number(max) + " in size, got " +
         vector(v);
}

std::optional<std::string> object_problem(const ObjectSpec& o) {
  if (auto p = position_problem(o.pose.position)) return p;
  if (auto p = orientation_problem(o.pose.orientation)) return p;
  if (o.ramp) {
    const RampGeometry& r = *o.ramp;
    if (!std::isfinite(r.angle) || r.angle <= 0 || r.angle >= M_PI / 2) {
      return "ramp angle must lie in (0, pi/2) rad, got " + number(r.angle);
    }
    if (auto p = size_problem(r.width, "ramp width")) return p;
    if (auto p = size_problem(r.height, "ramp height")) return p;
    if (auto p = size_problem(r.length(), "ramp length")) return p;
  }
  if (o.components.empty()) return std::string("an object needs at least one component");
  for (const auto& c : o.components) {
    if (auto p = component_problem(c)) return p;
  }
  if (!within(o.density, kMinDensity, kMaxDensity)) {
    return "density must lie in [" + number(kMinDensity) + ", " + number(kMaxDensity) +
           "] kg/m^3, got " + number(o.density);
  }
  if (o.portable && !within(o.mass(), kMinMass, kMaxMass)) {
    return "a portable object's mass must lie in [" + number(kMinMass) + ", " + number(kMaxMass) +
           "] kg, got " + number(o.mass());
  }
  return std::nullopt;
}

std::optional<std::string> physics_problem(const PhysicsSpec& p) {
  if (!within(p.step, kMinStep, kMaxStep)) {
    return "the step must lie in [" + number(kMinStep) + ", " + number(kMaxStep) + "] s, got " +
           number(p.step);
  }
  if (auto problem = magnitude_problem(p.gravity, kMaxGravity, "gravity")) return problem;
  if (p.solver_iterations < 1 || p.solver_iterations > kMaxSolverIterations) {
    return "solver iterations must lie in [1, " + std::to_string(kMaxSolverIterations) + "]";
  }
  if (!within(p.erp, 0, 1)) return "ERP must lie in [0, 1], got " + number(p.erp);
  if (!within(p.cfm, 0, 1)) return "CFM must lie in [0, 1], got " + number(p.cfm);
  return std::nullopt;
}

std::optional<std::string> material_problem(const MaterialSpec& m) {
  if (!within(m.friction, 0, kMaxFriction)) {
    return "friction must lie in [0, " + number(kMaxFriction) + "], got " + number(m.friction);
  }
  if (!within(m.bounce, 0, 1)) return "bounce must lie in [0, 1], got " + number(m.bounce);
  if (!within(m.bounce_velocity, 0, kMaxSpeed)) {
    return "bounce velocity must lie in [0, " + number(kMaxSpeed) + "] m/s";
  }
  if (!within(m.density, kMinDensity, kMaxDensity)) {
    return "density must lie in [" + number(kMinDensity) + ", " + number(kMaxDensity) +
           "] kg/m^3, got " + number(m.density);
  }
  return std::nullopt;
}

std::optional<std::string> joint_problem(const JointSpec& j) {
  if (!j.axis.allFinite() || j.axis.norm() < 1e-9 || j.axis.norm() > 1e9) {
    return "a joint's axis must be finite and not zero, got " + vector(j.axis);
  }
  if (auto p = position_problem(j.anchor)) return "a joint's anchor: " + *p;
  if (!within(j.lo, -kMaxCoordinate, kMaxCoordinate) ||
      !within(j.hi, -kMaxCoordinate, kMaxCoordinate) || j.lo > j.hi) {
    return "a joint's stops must be finite with lo <= hi, got " + number(j.lo) + " and " +
           number(j.hi);
  }
  if (!within(j.max_force, 0, kMaxForce)) {
    return "a joint's motor force must lie in [0, " + number(kMaxForce) + "], got " +
           number(j.max_force);
  }
  if (!within(std::abs(j.velocity), 0, kMaxSpeed)) {
    return "a joint's motor speed must be at most " + number(kMaxSpeed) + " in size, got " +
           number(j.velocity);
  }
  if (j.body1 == j.body2) return "a joint needs two different bodies, got '" + j.body1 + "' twice";
  return std::nullopt;
}

std::optional<std::string> robot_problem(const RobotSpec& r) {
  if (!robot_type_known(r.type)) {
    std::string known;
    for (const auto& name : robot_type_names()) known += (known.empty() ? "" : ", ") + name;
    return "unknown robot type '" + r.type + "' (known: " + known + ")";
  }
  if (auto p = position_problem(r.pose.position)) return p;
  if (auto p = orientation_problem(r.pose.orientation)) return p;
  if (!std::isfinite(r.encoder_rate) || r.encoder_rate <= 0 || r.encoder_rate > kMaxEncoderRate) {
    return "the encoder rate must lie in (0, " + number(kMaxEncoderRate) + "] Hz, got " +
           number(r.encoder_rate);
  }
  return std::nullopt;
}

void check_world(const WorldSpec& world) {
  auto fail = [](const SourceLocation& at, const std::string& file, const std::string& message) {
    throw WorldFileError(at.file.empty() ? file : at.file, at.line, message);
  };
  if (auto p = physics_problem(world.physics)) fail(world.physics.source, world.file, *p);
  if (!within(world.ground_friction, 0, kMaxFriction)) {
    fail({}, world.file, "the ground's friction must lie in [0, " + number(kMaxFriction) + "]");
  }
  for (const auto& m : world.materials) {
    if (auto p = material_problem(m))
      fail(m.source, world.file, "material '" + m.name + "': " + *p);
  }
  for (const auto& o : world.objects) {
    if (auto p = name_problem(o.name)) fail(o.source, world.file, *p);
    if (auto p = object_problem(o)) fail(o.source, world.file, "'" + o.name + "': " + *p);
  }
  for (const auto& j : world.joints) {
    if (auto p = joint_problem(j)) fail(j.source, world.file, "joint '" + j.name + "': " + *p);
  }
  for (const auto& r : world.robots) {
    if (auto p = robot_problem(r)) fail(r.source, world.file, "robot '" + r.name + "': " + *p);
  }
}

}  // namespace macsim::bounds
