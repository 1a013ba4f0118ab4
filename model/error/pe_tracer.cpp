#include "error/pe_tracer.h"

#include <memory>
#include <stdexcept>

namespace rtm {

namespace {
PeState pe_state(const Scene& s, const Grid& g, const MachineConfig& c) {
  PeState pe;
  pe.config = c;
  pe.image = std::make_shared<SceneImage>(s, g, c);
  return pe;
}
}  // namespace

PeTracer::PeTracer(const Scene& s, const Grid& g, const MachineConfig& c)
    : pe_(pe_state(s, g, c)), search_(pe_, 0), mac_(pe_, 0), root_(pe_, 0), shading_(pe_) {}

void PeTracer::trace(const Ray& ray, RayResult& out) {
  out.added = PixelSum{};
  out.spawned.clear();
  MachineRay& r = job_.r;
  r = MachineRay{};
  r.ray = ray;
  // Round the loop (front buffer, search, intersection) until a unit routes the ray out of it.
  FifoId to = FifoId::Search;
  while (to == FifoId::Search || to == FifoId::FeedbackSearch || to == FifoId::FeedbackIntersect) {
    to = search_.take(r, 0).out.fifo;
    if (to == kSearchToIntersect) {  // through any unit in between, unchanged
      mac_.take(job_, 0);
      to = root_.take(job_, 0).out.fifo;
    }
  }
  if (to == FifoId::Ends) {  // a blocked shadow ray, or a miss with no background to add
    out.end = ray.kind == RayKind::Shadow ? RayResult::End::Blocked : RayResult::End::Missed;
    out.prim = r.prim;
    return;
  }
  if (to != FifoId::Shade)
    throw std::logic_error("PeTracer: a unit routed a ray to an unexpected FIFO");
  int32_t id = -1;
  shading_.take(r, out.added, id, 0);
  for (size_t k = 1; k < shading_.outputs(); ++k) out.spawned.push_back(shading_.spawn(r, k).ray);
  shading_.retired();
  switch (r.arrival) {
    case MachineRay::Arrival::Hit:
      out.end = RayResult::End::Hit;
      break;
    case MachineRay::Arrival::LightReached:
      out.end = RayResult::End::LightReached;
      break;
    case MachineRay::Arrival::Missed:
      out.end = RayResult::End::Missed;
      break;
  }
  out.prim = r.prim;
  out.t = r.t_hit;
}

}  // namespace rtm
