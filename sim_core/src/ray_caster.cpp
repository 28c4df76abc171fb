#include "ray_caster.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "ode_support.h"

namespace macsim::detail {

RayCaster::RayCaster(dSpaceID space, int ignore_group)
    : space_(space), ignore_group_(ignore_group), ray_(dCreateRay(nullptr, 1.0)) {
  dGeomRaySetClosestHit(ray_, 1);
  dGeomRaySetFirstContact(ray_, 0);
  dGeomRaySetBackfaceCull(ray_, 0);
}

RayCaster::~RayCaster() { dGeomDestroy(ray_); }

void RayCaster::callback(void* data, dGeomID ray, dGeomID geom) {
  auto* self = static_cast<RayCaster*>(data);
  const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
  if (tag && tag->group == self->ignore_group_) return;
  dContactGeom contact;
  if (dCollide(ray, geom, 1, &contact, sizeof(dContactGeom)) == 1) {
    if (!self->hit_ || contact.depth < self->nearest_) self->nearest_ = contact.depth;
    self->hit_ = true;
  }
}

std::optional<double> RayCaster::cast(const Eigen::Vector3d& origin,
                                      const Eigen::Vector3d& direction, double max_range) {
  dGeomRaySetLength(ray_, max_range);
  dGeomRaySet(ray_, origin.x(), origin.y(), origin.z(), direction.x(), direction.y(),
              direction.z());
  hit_ = false;
  dSpaceCollide2(ray_, reinterpret_cast<dGeomID>(space_), this, &RayCaster::callback);
  if (!hit_) return std::nullopt;
  return nearest_;
}

namespace {

/// The geom's bounding box as min and max corners; false if it is unbounded (a plane).
bool bounds(dGeomID geom, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  dReal aabb[6];
  dGeomGetAABB(geom, aabb);
  lo = {aabb[0], aabb[2], aabb[4]};
  hi = {aabb[1], aabb[3], aabb[5]};
  return lo.allFinite() && hi.allFinite() && (hi - lo).maxCoeff() < 1e30;
}

/// Where the segment origin + t * direction, t in [0, length], enters the box, if it meets it
/// (slab test, widened by a millimetre so that rounding never sets aside a geom the ray touches):
/// no hit on the geom inside can be nearer.
std::optional<double> entry(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                            double length, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double enter = 0.0, leave = length;
  for (int k = 0; k < 3; ++k) {
    const double a = lo[k] - 1e-3, b = hi[k] + 1e-3;
    if (std::fabs(direction[k]) < 1e-12) {
      if (origin[k] < a || origin[k] > b) return std::nullopt;
      continue;
    }
    double t0 = (a - origin[k]) / direction[k], t1 = (b - origin[k]) / direction[k];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return std::nullopt;
  }
  return enter;
}

}  // namespace

void RayCaster::collect(dSpaceID space, std::vector<dGeomID>& out) const {
  const int n = dSpaceGetNumGeoms(space);
  for (int i = 0; i < n; ++i) {
    dGeomID g = dSpaceGetGeom(space, i);
    if (dGeomIsSpace(g)) {
      collect(reinterpret_cast<dSpaceID>(g), out);
      continue;
    }
    if (!dGeomIsEnabled(g)) continue;
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(g));
    if (tag && tag->group == ignore_group_) continue;
    // The category and collide bits, as dSpaceCollide2 looks at them.
    if (!(dGeomGetCategoryBits(ray_) & dGeomGetCollideBits(g)) &&
        !(dGeomGetCategoryBits(g) & dGeomGetCollideBits(ray_)))
      continue;
    out.push_back(g);
  }
}

std::optional<double> RayCaster::nearest_among(const Eigen::Vector3d& origin,
                                               const Eigen::Vector3d& direction, double max_range,
                                               const Candidates& geoms) {
  dGeomRaySetLength(ray_, max_range);
  dGeomRaySet(ray_, origin.x(), origin.y(), origin.z(), direction.x(), direction.y(),
              direction.z());
  hit_ = false;
  for (dGeomID g : geoms.unbounded) callback(this, ray_, g);
  // The boxes the ray crosses, nearest entry first: once a hit is nearer than the next entry,
  // nothing further can be nearer.
  entered_.clear();
  for (std::size_t i = 0; i < geoms.near.size(); ++i) {
    const auto& [lo, hi] = geoms.boxes[i];
    if (const auto t = entry(origin, direction, max_range, lo, hi)) {
      entered_.emplace_back(*t, i);
    }
  }
  std::sort(entered_.begin(), entered_.end());
  for (const auto& [t, i] : entered_) {
    if (hit_ && t > nearest_) break;
    callback(this, ray_, geoms.near[i]);
  }
  if (!hit_) return std::nullopt;
  return nearest_;
}

RayCaster::Candidates RayCaster::candidates(
    const std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&)>& reachable) const {
  std::vector<dGeomID> all;
  collect(space_, all);
  Candidates geoms;
  for (dGeomID g : all) {
    Eigen::Vector3d lo, hi;
    if (!bounds(g, lo, hi)) {
      geoms.unbounded.push_back(g);
    } else if (reachable(lo, hi)) {
      geoms.near.push_back(g);
      geoms.boxes.emplace_back(lo, hi);
    }
  }
  return geoms;
}

std::vector<std::optional<double>> RayCaster::cast_fan(
    const Eigen::Vector3d& origin, const std::vector<Eigen::Vector3d>& directions,
    double max_range) {
  // The fan's plane, if all its rays lie in one.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  if (directions.size() >= 2) {
    for (const auto& d : directions) {
      normal = directions.front().cross(d);
      if (normal.norm() > 1e-3) break;
    }
    normal.normalize();
    for (const auto& d : directions) {
      if (!normal.allFinite() || std::fabs(normal.dot(d)) > 1e-9) {
        normal.setZero();
        break;
      }
    }
  }
  // Set aside what no ray of the fan reaches: out of range, or (planar fan) off its plane.
  const Candidates geoms = candidates([&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const Eigen::Vector3d closest = origin.cwiseMax(lo).cwiseMin(hi);
    if ((closest - origin).norm() > max_range + 1e-3) return false;
    if (normal.isZero()) return true;
    const Eigen::Vector3d centre = (lo + hi) / 2, half = (hi - lo) / 2;
    return std::fabs(normal.dot(centre - origin)) <= half.dot(normal.cwiseAbs()) + 1e-3;
  });
  std::vector<std::optional<double>> hits;
  hits.reserve(directions.size());
  for (const auto& d : directions) hits.push_back(nearest_among(origin, d, max_range, geoms));
  return hits;
}

std::vector<std::optional<double>> RayCaster::cast_bundle(const std::vector<Ray>& rays) {
  std::vector<std::optional<double>> hits;
  if (rays.empty()) return hits;
  // The box that holds every ray, widened as entry() widens boxes.
  Eigen::Vector3d reach_lo = rays.front().origin, reach_hi = rays.front().origin;
  for (const Ray& r : rays) {
    const Eigen::Vector3d end = r.origin + r.max_range * r.direction;
    reach_lo = reach_lo.cwiseMin(r.origin).cwiseMin(end);
    reach_hi = reach_hi.cwiseMax(r.origin).cwiseMax(end);
  }
  reach_lo.array() -= 2e-3;
  reach_hi.array() += 2e-3;
  const Candidates geoms = candidates([&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return (lo.array() <= reach_hi.array()).all() && (hi.array() >= reach_lo.array()).all();
  });
  hits.reserve(rays.size());
  for (const Ray& r : rays) {
    hits.push_back(nearest_among(r.origin, r.direction, r.max_range, geoms));
  }
  return hits;
}

}  // namespace macsim::detail
