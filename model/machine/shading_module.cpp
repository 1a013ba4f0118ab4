#include "machine/shading_module.h"

namespace rtm {

ShadingModule::ShadingModule(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem)
    : UnitModule(name, ctx, {UnitKind::Shading}), unit_(ctx), sleep_(ctx.sleeper(UnitKind::Shading)), mem_(mem) {
  if (ctx.units.shadow_rays) generators_[size_t(RayKind::Shadow)] = std::make_unique<SpawnUnit>("shadow_rays");
  if (ctx.units.reflection) generators_[size_t(RayKind::Reflected)] = std::make_unique<SpawnUnit>("reflection");
  if (ctx.units.refraction) generators_[size_t(RayKind::Transmitted)] = std::make_unique<SpawnUnit>("refraction");
  SC_THREAD(run);
}

void ShadingModule::trace(Waveform& wave) {
  probe_.trace(wave, name(), &ctx_.window);
  for (auto& g : generators_)
    if (g) g->probe.trace(wave, g->name(), &ctx_.window);
}

void ShadingModule::run() {
  for (;;) {
    const MachineRay r = rays_in(FifoId::Shade)->read();
    probe_.begin(r.id);
    const uint64_t cycles = unit_.take(r, mem_.frame[r.slot], mem_.ids[r.slot], ctx_.log_time());
    for (size_t k = 1; k < unit_.outputs(); ++k) generators_[size_t(unit_.spawned_kind(k - 1))]->probe.begin(r.id);
    (*sleep_)(ctx_.cycles(cycles));
    for (auto& g : generators_)
      if (g) g->probe.end();
    write(unit_.output(0), r, UnitKind::Shading, 0, *sleep_);
    for (size_t k = 1; k < unit_.outputs(); ++k) write(unit_.output(k), unit_.spawn(r, k), UnitKind::Shading, 0, *sleep_);
    probe_.end();
  }
}

}  // namespace rtm
