// Casts rays into a world's collision space with one reusable ODE ray geom.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <optional>

namespace macsim::detail {

/// Distances along rays to the nearest geom, skipping one collision group (the robot itself).
class RayCaster {
 public:
  RayCaster(dSpaceID space, int ignore_group);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// Distance (m) to the first hit from `origin` along the unit vector `direction`, if any
  /// within `max_range`.
  std::optional<double> cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                             double max_range);

 private:
  static void callback(void* data, dGeomID ray, dGeomID geom);

  dSpaceID space_;
  int ignore_group_;
  dGeomID ray_;
  double nearest_ = 0.0;
  bool hit_ = false;
};

}  // namespace macsim::detail
