// Casts rays into a world's collision space with one reusable ODE ray geom.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

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
  /// cast() for a fan of rays from one origin (a laser sweep), the same answers: geoms that no
  /// ray of the fan can reach (out of range, wholly behind a fan of up to 180 degrees, off a
  /// planar fan's plane) are set aside once, and each ray is tested only against the rest whose
  /// bounding box it crosses; planes a ray surely misses are not tested.
  std::vector<std::optional<double>> cast_fan(const Eigen::Vector3d& origin,
                                              const std::vector<Eigen::Vector3d>& directions,
                                              double max_range);
  /// One ray of a bundle: from `origin` along the unit vector `direction`, up to `max_range`.
  struct Ray {
    Eigen::Vector3d origin, direction;
    double max_range;
  };
  /// cast() for rays from anywhere (a robot's range sensors), the same answers: the geoms
  /// outside the box that holds all the rays are set aside once, and each ray is tested only
  /// against the rest whose bounding box it crosses.
  std::vector<std::optional<double>> cast_bundle(const std::vector<Ray>& rays);

 private:
  static void callback(void* data, dGeomID ray, dGeomID geom);
  /// The geoms of `space` (and its sub-spaces) a ray may hit: enabled, not ignored.
  void collect(dSpaceID space, std::vector<dGeomID>& out) const;
  /// Geoms a set of rays may hit: the unbounded ones (planes) and the rest with their boxes.
  struct Candidates {
    std::vector<dGeomID> unbounded, near;
    std::vector<Eigen::Vector4d> planes;  // of `unbounded`: (normal, offset), NaN if no plane
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes;  // of `near`
  };
  /// The geoms of the space rays may hit: the unbounded ones, and those whose box (min, max
  /// corners) `reachable` keeps. Filled into the caster's own lists (their storage kept).
  const Candidates& candidates(
      const std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&)>& reachable);
  /// The nearest hit of one ray among `geoms`, testing the boxes it crosses nearest first.
  std::optional<double> nearest_among(const Eigen::Vector3d& origin,
                                      const Eigen::Vector3d& direction, double max_range,
                                      const Candidates& geoms);

  dSpaceID space_;
  int ignore_group_;
  dGeomID ray_;
  double nearest_ = 0.0;
  bool hit_ = false;
  std::vector<std::pair<double, std::size_t>> entered_;  // (entry distance, index in near)
  std::vector<dGeomID> collected_;                       // candidates()'s work list
  Candidates candidates_;                                // what candidates() gave last
};

}  // namespace macsim::detail
