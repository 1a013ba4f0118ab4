#include "machine/shading_module.h"

namespace rtm {

ShadingModule::ShadingModule(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem)
    : UnitModule(name, ctx, {UnitKind::Shading}),
      unit_(ctx),
      sleep_(ctx.sleeper(UnitKind::Shading)),
      mem_(mem),
      pipe_(ctx.period.value(), &ctx.counters.unit(UnitKind::Shading, 0)) {
  if (ctx.units.shadow_rays)
    generators_[size_t(RayKind::Shadow)] = std::make_unique<SpawnUnit>("shadow_rays");
  if (ctx.units.reflection)
    generators_[size_t(RayKind::Reflected)] = std::make_unique<SpawnUnit>("reflection");
  if (ctx.units.refraction)
    generators_[size_t(RayKind::Transmitted)] = std::make_unique<SpawnUnit>("refraction");
  SC_THREAD(run);
}

void ShadingModule::trace(Waveform& wave) {
  probe_.trace(wave, name(), &ctx_.window);
  for (auto& g : generators_)
    if (g) g->probe.trace(wave, g->name(), &ctx_.window);
}

/// Shading's operations for ShadingWriter: `r` is the oldest shaded ray.
struct ShadingModule::WriteOps {
  ShadingModule& m;
  const MachineRay& r;

  bool write_end(const Output& o) { return m.try_write(o, r, UnitKind::Shading, 0); }
  MachineRay make(size_t k) {
    if (auto& g = m.generators_[size_t(m.unit_.spawned_kind(k - 1))]) g->probe.begin(r.id);
    return m.unit_.spawn(r, k);
  }
  bool write(const Output& o, const MachineRay& child) {
    return m.try_write(o, child, UnitKind::Shading, 0);
  }
};

struct ShadingModule::Ops {
  ShadingModule& m;

  void woke(uint64_t) {}
  bool write_head(uint64_t) {
    WriteOps ops{m, m.pipe_.head().item};
    return m.writer_.write(m.unit_, ops);
  }
  void retired(const MachineRay&) {
    m.unit_.retired();
    m.writer_.retired();
    if (!m.pipe_.empty()) return;
    m.probe_.end();
    for (auto& g : m.generators_)
      if (g) g->probe.end();
  }
  bool accept(uint64_t now) {
    MachineRay r;
    if (!m.rays_in(FifoId::Shade)->nb_read(r)) return false;
    m.probe_.begin(r.id);
    Work w = m.unit_.take(r, m.mem_.frame[r.slot], m.mem_.ids[r.slot], now);
    m.pipe_.accept(r, now, w.cycles, w.interval, std::move(w.wait));
    return true;
  }
  bool wait_for_input() { return true; }
  void want(uint64_t t) { m.sleep_->want(t); }
};

void ShadingModule::run() {
  Ops ops{*this};
  const sc_core::sc_event_or_list either =
      rays_in(FifoId::Shade)->data_written_event() | sleep_->event();
  run_unit(pipe_, ops, *sleep_, either);
}

}  // namespace rtm
