#include "machine/shading_stage.h"

namespace rtm {

ShadingStage::ShadingStage(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem)
    : sc_module(name), ctx_(ctx), sleep_(ctx.sleeper()), mem_(mem) {
  if (ctx.units.shadow_rays) units_[size_t(RayKind::Shadow)] = std::make_unique<SpawnUnit>("shadow_rays");
  if (ctx.units.reflection) units_[size_t(RayKind::Reflected)] = std::make_unique<SpawnUnit>("reflection");
  if (ctx.units.refraction) units_[size_t(RayKind::Transmitted)] = std::make_unique<SpawnUnit>("refraction");
  SC_THREAD(run);
}

void ShadingStage::trace(sc_core::sc_trace_file* tf, const std::string& prefix) {
  probe_.trace(tf, prefix, &ctx_.window);
  for (auto& u : units_)
    if (u) u->probe.trace(tf, std::string(u->name()), &ctx_.window);
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
    for (const Ray& child : out.rays) {
      SpawnUnit* u = units_[size_t(child.kind)].get();
      if (!u) SC_REPORT_FATAL("rtm/pe/shading", "a left-out ray generator was needed: the scene analysis is wrong");
      ++u->rays;
      u->probe.begin(r.id);
    }
    (*sleep_)(ctx_.cycles(cycles));
    for (auto& u : units_)
      if (u) u->probe.end();
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
