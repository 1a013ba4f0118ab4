#include "machine/shading_module.h"

namespace rtm {

ShadingModule::ShadingModule(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem)
    : UnitModule(name, ctx, {UnitKind::Shading}), unit_(ctx), sleep_(ctx.sleeper(UnitKind::Shading)), mem_(mem),
      pipe_(ctx.period.value(), &ctx.counters.unit(UnitKind::Shading, 0)) {
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

struct ShadingModule::Ops {
  ShadingModule& m;
  bool waiting = false;
  sc_core::sc_event_or_list either;

  void woke(uint64_t) {}
  bool write_head(uint64_t) {
    // The end first, then each spawned ray, made (numbered) before it waits for room.
    const MachineRay& r = m.pipe_.head().item;
    for (; m.next_output_ < m.unit_.outputs(); ++m.next_output_) {
      const Output o = m.unit_.output(m.next_output_);
      if (m.next_output_ == 0) {
        if (!m.try_write(o, r, UnitKind::Shading, 0)) return false;
        continue;
      }
      if (!m.child_made_) {
        if (auto& g = m.generators_[size_t(m.unit_.spawned_kind(m.next_output_ - 1))]) g->probe.begin(r.id);
        m.child_ = m.unit_.spawn(r, m.next_output_);
        m.child_made_ = true;
      }
      if (!m.try_write(o, m.child_, UnitKind::Shading, 0)) return false;
      m.child_made_ = false;
    }
    return true;
  }
  void retired(const MachineRay&) {
    m.unit_.retired();
    m.next_output_ = 0;
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
  void wait_for_input() { waiting = true; }
  void want(uint64_t t) { m.sleep_->want(t); }
};

void ShadingModule::run() {
  Ops ops{*this, false, {}};
  ops.either = rays_in(FifoId::Shade)->data_written_event() | sleep_->event();
  run_unit(pipe_, ops, *sleep_);
}

}  // namespace rtm
