#include "machine/shading_stage.h"

namespace rtm {

ShadingStage::ShadingStage(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem)
    : sc_module(name), ctx_(ctx), mem_(mem) {
  SC_THREAD(run);
}

void ShadingStage::run() {
  const MachineConfig& c = ctx_.config;
  ShadeOut out;
  for (;;) {
    const MachineRay r = rays_in->read();
    probe_.begin(r.id);
    const Scene& s = *ctx_.image->scene;
    PixelSum& pixel = mem_.frame[r.slot];
    out.rays.clear();
    uint64_t cycles = 0;
    switch (r.arrival) {
      case MachineRay::Arrival::Hit:
        if (r.ray.kind == RayKind::Primary) mem_.ids[r.slot] = int32_t(r.prim);
        shade_hit(s, r.ray, r.t_hit, s.primitives[r.prim], out);
        pixel.add(out.brightness);
        cycles = uint64_t(c.shade_cycles) + uint64_t(c.spawn_cycles) * out.rays.size();
        break;
      case MachineRay::Arrival::LightReached:
        pixel.add(r.ray.brightness);
        cycles = uint64_t(c.accumulate_cycles);
        break;
      case MachineRay::Arrival::Missed:
        pixel.add(miss_brightness(s, r.ray));
        cycles = uint64_t(c.accumulate_cycles);
        break;
    }
    ctx_.counters.shade.busy_cycles += cycles;
    ++ctx_.counters.shade.items;
    sc_core::wait(ctx_.cycles(cycles));
    ends_out->write(RayEnd{r.id});
    for (const Ray& child : out.rays) {
      MachineRay m;
      m.ray = child;
      m.slot = r.slot;
      m.id = ctx_.next_ray_id++;
      ++ctx_.counters.counts.rays[size_t(child.kind)];
      spawn_out->write(m);
    }
    probe_.end();
  }
}

}  // namespace rtm
