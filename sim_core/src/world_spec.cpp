#include "macsim/sim_core/world_spec.h"

#include <algorithm>
#include <cmath>

namespace macsim {

const char* shape_name(Shape shape) {
  switch (shape) {
    case Shape::Box:
      return "BOX";
    case Shape::Cylinder:
      return "CYLINDER";
    case Shape::Sphere:
      return "SPHERE";
  }
  return "?";
}

double component_volume(const ComponentSpec& c) {
  switch (c.shape) {
    case Shape::Box:
      return c.size.x() * c.size.y() * c.size.z();
    case Shape::Cylinder:
      return M_PI * c.size.x() * c.size.x() * c.size.z();
    case Shape::Sphere:
      return 4.0 / 3.0 * M_PI * std::pow(c.size.x(), 3);
  }
  return 0.0;
}

RampGeometry RampGeometry::from_depth(double width, double depth, double angle) {
  return {width, depth * std::tan(angle), angle};
}

namespace {
ObjectSpec primitive(Shape shape, const Eigen::Vector3d& position, const Eigen::Vector3d& size,
                     bool portable, const std::string& user_data) {
  ObjectSpec spec;
  spec.portable = portable;
  spec.user_data = user_data;
  spec.pose.position = position;
  ComponentSpec c;
  c.shape = shape;
  c.size = size;
  spec.components.push_back(c);
  return spec;
}
}  // namespace

ObjectSpec box_object(const Eigen::Vector3d& position, const Eigen::Vector3d& size, bool portable,
                      const std::string& user_data) {
  return primitive(Shape::Box, position, size, portable, user_data);
}

ObjectSpec cylinder_object(const Eigen::Vector3d& position, double radius, double height,
                           bool portable, const std::string& user_data) {
  return primitive(Shape::Cylinder, position, {radius, 0.0, height}, portable, user_data);
}

ObjectSpec sphere_object(const Eigen::Vector3d& position, double radius, bool portable,
                         const std::string& user_data) {
  return primitive(Shape::Sphere, position, {radius, 0.0, 0.0}, portable, user_data);
}

double RampGeometry::depth() const { return height / std::tan(angle); }

double RampGeometry::length() const { return std::hypot(depth(), height); }

ComponentSpec RampGeometry::box() const {
  // The top face runs from the foot (0, 0) up to (depth, height); the box is just thick
  // enough (height / cos angle) for its high end to reach the floor, the rest is buried.
  const double thickness = height / std::cos(angle);
  ComponentSpec box;
  box.shape = Shape::Box;
  box.size = {length(), width, thickness};
  box.pose.position = {depth() / 2 + thickness / 2 * std::sin(angle), 0.0,
                       height / 2 - thickness / 2 * std::cos(angle)};
  box.pose.orientation = Eigen::AngleAxisd(-angle, Eigen::Vector3d::UnitY());
  return box;
}

double ObjectSpec::volume() const {
  double v = 0.0;
  for (const auto& c : components) v += component_volume(c);
  return v;
}

const MaterialSpec* WorldSpec::material(const std::string& material_name) const {
  for (const auto& m : materials) {
    if (m.name == material_name) return &m;
  }
  return nullptr;
}

const ObjectSpec* WorldSpec::object(const std::string& object_name) const {
  for (const auto& o : objects) {
    if (o.name == object_name) return &o;
  }
  return nullptr;
}

void normalize_orientations(ObjectSpec& object) {
  object.pose.orientation.normalize();
  for (auto& c : object.components) c.pose.orientation.normalize();
}

double footprint_radius(const ObjectSpec& object) {
  double radius = 0.0;
  for (const auto& c : object.components) {
    const Eigen::Quaterniond q = object.pose.orientation * c.pose.orientation;
    const double offset = (object.pose.orientation * c.pose.position).head<2>().norm();
    double half = 0;
    if (c.shape == Shape::Sphere || std::fabs((q * Eigen::Vector3d::UnitZ()).z()) > 0.999) {
      // Standing upright (turned about the vertical at most): its cross-section.
      half = c.shape == Shape::Box ? 0.5 * c.size.head<2>().norm() : c.size.x();
    } else {
      // Tilted or lying (a cylinder on its side): the farthest corner of its box, seen from above.
      const Eigen::Vector3d box = c.shape == Shape::Box
                                      ? Eigen::Vector3d(c.size / 2)
                                      : Eigen::Vector3d(c.size.x(), c.size.x(), c.size.z() / 2);
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner((k & 1 ? 1 : -1) * box.x(), (k & 2 ? 1 : -1) * box.y(),
                                     (k & 4 ? 1 : -1) * box.z());
        half = std::max(half, (q * corner).head<2>().norm());
      }
    }
    radius = std::max(radius, offset + half);
  }
  return radius;
}

}  // namespace macsim
