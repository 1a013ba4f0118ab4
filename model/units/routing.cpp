#include "units/routing.h"

namespace rtm {

namespace {
/// A walk that ended without a hit: a shadow ray has reached its light; a primary or branch ray
/// ends, going through shading only when there is a background to add.
Route exit_route(const Scene& s, MachineRay& r) {
  if (r.ray.kind == RayKind::Shadow) {
    r.arrival = MachineRay::Arrival::LightReached;
    return Route::Shade;
  }
  r.arrival = MachineRay::Arrival::Missed;
  return s.background != Vec3(0, 0, 0) ? Route::Shade : Route::End;
}
}  // namespace

template <class Real>
bool search_pass(const Grid& g, MachineRay& r) {
  using Walk = BasicDda<Real>;
  const Ray& ray = r.ray;
  if (!r.started) {
    r.walk = Walk::start(g, ray.origin, ray.dir, 0.0, ray.t_max);
    r.started = true;
  }
  if (r.walk.done) return false;
  r.examined = r.walk;
  r.last = Walk::is_last(g, ray.dir, ray.t_max, r.walk);
  Walk::advance(g, ray.origin, ray.dir, ray.t_max, r.walk);
  return true;
}
template bool search_pass<float>(const Grid&, MachineRay&);
template bool search_pass<double>(const Grid&, MachineRay&);

Route search_route(const Scene& s, const Grid& g, MachineRay& r, bool examined) {
  if (!examined) return exit_route(s, r);
  const DdaState& e = r.examined;
  if (g.count(g.index(e.cell[0], e.cell[1], e.cell[2])) > 0) return Route::Intersect;
  return r.last ? exit_route(s, r) : Route::Feedback;
}

Route intersection_route(const Scene& s, MachineRay& r, const VoxelHit& h) {
  if (h.hit) {
    if (r.ray.kind == RayKind::Shadow) {  // the light is blocked
      r.prim = h.prim;                    // for the error attribution (error/error_causes.h)
      return Route::End;
    }
    r.arrival = MachineRay::Arrival::Hit;
    r.t_hit = h.t;
    r.prim = h.prim;
    return Route::Shade;
  }
  return r.last ? exit_route(s, r) : Route::Feedback;
}

}  // namespace rtm
