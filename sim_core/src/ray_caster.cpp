#include "ray_caster.h"

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

}  // namespace macsim::detail
