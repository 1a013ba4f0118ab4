#include "units/shading_unit.h"

#include <algorithm>
#include <stdexcept>

namespace rtm {

Work ShadingUnit::take(const MachineRay& r, PixelSum& pixel, int32_t& primary_id, uint64_t now) {
  const MachineConfig& c = pe_.config;
  const Scene& s = *pe_.image->scene;
  // Grow the ring when full, keeping its order (head_ .. taken_ − 1).
  if (taken_ - head_ == outs_.size()) {
    std::vector<ShadeOut> grown(outs_.size() * 2 + 1);
    for (size_t i = head_; i < taken_; ++i) grown[i - head_] = std::move(outs_[i % outs_.size()]);
    outs_ = std::move(grown);
    taken_ -= head_;
    head_ = 0;
  }
  ShadeOut& out = outs_[taken_++ % outs_.size()];
  out.rays.clear();
  uint64_t cycles = 0;
  const bool fp32 = c.shading_precision_in_force() == Precision::Fp32;
  switch (r.arrival) {
    case MachineRay::Arrival::Hit:
      if (r.ray.kind == RayKind::Primary) primary_id = int32_t(r.prim);
      if (fp32)
        shade_hit<float>(s, r.ray, r.t_hit, s.primitives[r.prim], c.hit_refine,
                         c.normal_interpolation, out);
      else
        shade_hit<double>(s, r.ray, r.t_hit, s.primitives[r.prim], c.hit_refine,
                          c.normal_interpolation, out);
      pixel.add(out.brightness);
      cycles = uint64_t(c.shade_cycles) + uint64_t(c.refine_cycles_in_force()) +
               uint64_t(c.interpolate_cycles_for(s.primitives[r.prim])) +
               uint64_t(c.spawn_cycles) * out.rays.size();
      break;
    case MachineRay::Arrival::LightReached:
      pixel.add(r.ray.brightness);
      cycles = uint64_t(c.accumulate_cycles);
      break;
    case MachineRay::Arrival::Missed:
      pixel.add(fp32 ? miss_brightness<float>(s, r.ray) : miss_brightness<double>(s, r.ray));
      cycles = uint64_t(c.accumulate_cycles);
      break;
  }
  for (const Ray& child : out.rays)
    if (!pe_.units.generates(child.kind))
      throw std::logic_error("a left-out ray generator was needed: the scene analysis is wrong");
  // Counted now, before the ray's end (its first output) could leave its pixel without rays.
  pe_.rays_made(r.slot, out.rays.size());
  Work w{cycles, pipeline_interval(c.shade_interval, cycles), output(0), {}};
  if (PeMemory* m = pe_.memory.get()) {
    // The pixel's brightness is read, added to and written back within the unit's cycles.
    const uint64_t at = m->addresses().frame_entry(pe_.place_in_frame(r.slot)),
                   cycle = now / pe_.cycle;
    w.wait.latency = cycles;
    m->request(m->shading(), at, kBrightnessBytes, cycle,
               std::max(cycles, m->unloaded(kBrightnessBytes)), w.wait);
    m->post(m->shading(), at, kBrightnessBytes, cycle);
  }
  if (pe_.log) pe_.log->take(now, UnitKind::Shading, 0, r.id, cycles);
  return w;
}

MachineRay ShadingUnit::spawn(const MachineRay& parent, size_t k) {
  const Ray& child = head().rays[k - 1];
  MachineRay m;
  m.ray = child;
  m.slot = parent.slot;
  m.id = pe_.next_ray_id++;
  ++pe_.counters.counts.rays[size_t(child.kind)];
  return m;
}

}  // namespace rtm
