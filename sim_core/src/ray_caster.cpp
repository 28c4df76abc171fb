#include "ray_caster.h"

#include <algorithm>
#include <cassert>
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
/// no hit on the geom inside can be nearer. `inverse` holds 1 / direction per axis, 0 on an
/// axis the ray runs across (|direction| < 1e-12).
std::optional<double> entry(const Eigen::Vector3d& origin, const Eigen::Vector3d& inverse,
                            double length, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double enter = 0.0, leave = length;
  for (int k = 0; k < 3; ++k) {
    const double a = lo[k] - 1e-3, b = hi[k] + 1e-3;
    if (inverse[k] == 0.0) {
      if (origin[k] < a || origin[k] > b) return std::nullopt;
      continue;
    }
    double t0 = (a - origin[k]) * inverse[k], t1 = (b - origin[k]) * inverse[k];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return std::nullopt;
  }
  return enter;
}

/// True if the ray surely misses the plane n.x = offset (p = (n, offset)): it runs away from
/// it, or meets it beyond `length`. Conservative by a micrometre: rays near either edge are
/// left to the collider, whose answer alone counts.
bool misses_plane(const Eigen::Vector4d& p, const Eigen::Vector3d& origin,
                  const Eigen::Vector3d& direction, double length) {
  if (!p.allFinite()) return false;
  const double k = p.head<3>().dot(direction);
  if (std::fabs(k) < 1e-9) return false;
  const double t = (p[3] - p.head<3>().dot(origin)) / k;
  return t < -1e-6 || t > length + 1e-6;
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
  // Distances along the ray, the slab test's and the planes' culling, count in its direction's
  // length: a unit one (callers rotate unit vectors) makes them metres.
  assert(std::fabs(direction.squaredNorm() - 1.0) < 1e-9 &&
         "a ray's direction must be a unit vector");
  // The ray geom is placed only once a geom is to be tested: most rays of a sweep meet no box
  // and miss the floor, and cost no collider call at all.
  bool placed = false;
  auto test = [&](dGeomID g) {
    if (!placed) {
      dGeomRaySetLength(ray_, max_range);
      dGeomRaySet(ray_, origin.x(), origin.y(), origin.z(), direction.x(), direction.y(),
                  direction.z());
      placed = true;
    }
    callback(this, ray_, g);
  };
  hit_ = false;
  for (std::size_t i = 0; i < geoms.unbounded.size(); ++i) {
    if (!misses_plane(geoms.planes[i], origin, direction, max_range)) test(geoms.unbounded[i]);
  }
  // The boxes the ray crosses, nearest entry first: once a hit is nearer than the next entry,
  // nothing further can be nearer.
  entered_.clear();
  Eigen::Vector3d inverse;
  for (int k = 0; k < 3; ++k)
    inverse[k] = std::fabs(direction[k]) < 1e-12 ? 0.0 : 1.0 / direction[k];
  for (std::size_t i = 0; i < geoms.near.size(); ++i) {
    const auto& [lo, hi] = geoms.boxes[i];
    if (const auto t = entry(origin, inverse, max_range, lo, hi)) {
      entered_.emplace_back(*t, i);
    }
  }
  if (entered_.size() > 1) std::sort(entered_.begin(), entered_.end());
  for (const auto& [t, i] : entered_) {
    if (hit_ && t > nearest_) break;
    test(geoms.near[i]);
  }
  if (!hit_) return std::nullopt;
  return nearest_;
}

const RayCaster::Candidates& RayCaster::candidates(
    const std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&)>& reachable) {
  collected_.clear();
  collect(space_, collected_);
  Candidates& geoms = candidates_;
  geoms.unbounded.clear();
  geoms.near.clear();
  geoms.planes.clear();
  geoms.boxes.clear();
  for (dGeomID g : collected_) {
    Eigen::Vector3d lo, hi;
    if (!bounds(g, lo, hi)) {
      geoms.unbounded.push_back(g);
      dVector4 p;
      if (dGeomGetClass(g) == dPlaneClass) {
        dGeomPlaneGetParams(g, p);
        geoms.planes.emplace_back(p[0], p[1], p[2], p[3]);
      } else {
        geoms.planes.push_back(Eigen::Vector4d::Constant(std::nan("")));
      }
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
  // The half-space ahead of the fan, if no ray of it points backwards from its middle one
  // (a scanner's fan of up to 180 degrees): what lies wholly behind is out of its reach.
  Eigen::Vector3d ahead = Eigen::Vector3d::Zero();
  if (!directions.empty()) {
    ahead = directions[directions.size() / 2];
    for (const auto& d : directions) {
      if (!ahead.allFinite() || ahead.dot(d) < 0.0) {
        ahead.setZero();
        break;
      }
    }
  }
  // Set aside what no ray of the fan reaches: out of range, behind it, or (planar fan) off its
  // plane.
  const Candidates& geoms = candidates([&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const Eigen::Vector3d closest = origin.cwiseMax(lo).cwiseMin(hi);
    if ((closest - origin).norm() > max_range + 1e-3) return false;
    const Eigen::Vector3d centre = (lo + hi) / 2, half = (hi - lo) / 2;
    if (ahead.dot(centre - origin) + half.dot(ahead.cwiseAbs()) < -1e-3) return false;
    if (normal.isZero()) return true;
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
  const Candidates& geoms = candidates([&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return (lo.array() <= reach_hi.array()).all() && (hi.array() >= reach_lo.array()).all();
  });
  hits.reserve(rays.size());
  for (const Ray& r : rays) {
    hits.push_back(nearest_among(r.origin, r.direction, r.max_range, geoms));
  }
  return hits;
}

}  // namespace macsim::detail
