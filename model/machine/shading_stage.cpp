#include "machine/shading_stage.h"

#include "machine/unit_work.h"

namespace rtm {

ShadingStage::ShadingStage(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem)
    : sc_module(name), ctx_(ctx), sleep_(ctx.sleeper(UnitRank::Shading)), mem_(mem) {
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
  ShadeOut out;
  for (;;) {
    const MachineRay r = rays_in->read();
    probe_.begin(r.id);
    const uint64_t cycles = shade_work(ctx_, r, mem_.frame[r.slot], mem_.ids[r.slot], out);
    for (const Ray& child : out.rays) {
      SpawnUnit* u = units_[size_t(child.kind)].get();
      if (!u) SC_REPORT_FATAL("rtm/pe/shading", "a left-out ray generator was needed: the scene analysis is wrong");
      u->probe.begin(r.id);
    }
    (*sleep_)(ctx_.cycles(cycles));
    for (auto& u : units_)
      if (u) u->probe.end();
    put(ends_out, RayEnd{r.id}, ctx_, *sleep_);
    for (const Ray& child : out.rays) put(spawn_out, spawned_ray(ctx_, r, child), ctx_, *sleep_);
    probe_.end();
  }
}

}  // namespace rtm
