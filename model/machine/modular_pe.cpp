#include "machine/modular_pe.h"

#include <set>

#include "units/fifo_report.h"

namespace rtm {
ModularPe::ModularPe(sc_core::sc_module_name name, int index, const MachineConfig& c,
                     const PeUnits& units, size_t pixels, sc_core::sc_clock* clock,
                     Timekeeper* keeper)
    : Pe(name, index, c, units, pixels, keeper) {
  for (const FifoSpec& f : fifo_table()) {
    if (f.per_lane || !units.has(f)) continue;
    if (f.payload == Payload::Ray)
      rays_[size_t(f.id)] = std::make_unique<MeteredFifo<MachineRay>>(f.name, c.*f.depth, f.kind);
    else
      ends_ = std::make_unique<MeteredFifo<RayEnd>>(f.name, c.*f.depth, f.kind);
  }
  // In the unit table's order: the kernel's order among processes runnable together follows it
  // (arbitration = kernel).
  for (const UnitSpec& u : unit_table())
    for (int k = 0, n = unit_count(u.kind, c); k < n; ++k)
      create(u.kind, k, c.timing == Timing::Clocked ? clock : nullptr);

  for (const FifoSpec& f : fifo_table()) {
    if (f.per_lane || !units.has(f)) continue;
    std::set<UnitModule*> ends;  // a module running several units binds each FIFO once
    for (const auto* kinds : {&f.writers, &f.readers})
      for (UnitKind k : *kinds)
        for (UnitModule* m : modules_[size_t(k)]) ends.insert(m);
    for (UnitModule* m : ends) {
      if (f.payload == Payload::Ray)
        m->bind(f.id, *rays_[size_t(f.id)]);
      else
        m->bind(f.id, *ends_);
    }
  }
}

void ModularPe::create(UnitKind kind, int k, sc_core::sc_clock* clock) {
  const MachineConfig& c = ctx.config;
  std::vector<UnitModule*>& of = modules_[size_t(kind)];
  switch (kind) {
    case UnitKind::FrontBuffer:
      front_ = std::make_unique<FrontBufferModule>(unit_name(kind), ctx, memory, finished_event);
      return of.push_back(front_.get());
    case UnitKind::Shading:
      shading_ = std::make_unique<ShadingModule>(unit_name(kind), ctx, memory);
      return of.push_back(shading_.get());
#define RTM_RAY_STAGE_CASE(K, Class) \
  case UnitKind::K:                  \
    return of.push_back(create_stage<UnitKind::K>(k));
      RTM_RAY_STAGES(RTM_RAY_STAGE_CASE)
#undef RTM_RAY_STAGE_CASE
    case UnitKind::Mac:
      // An intersection unit runs its lane's MAC and root unit.
      if (k == 0)
        intersect_dispatch_ = std::make_unique<Dispatcher>(
            "intersect_dispatch", *rays_[size_t(FifoId::Intersect)], c.intersection_units);
      intersection_.push_back(std::make_unique<IntersectionModule>(
          ("intersection" + std::to_string(k)).c_str(), ctx, clock, *intersect_dispatch_, k));
      return of.push_back(intersection_.back().get());
    case UnitKind::Root:
      return of.push_back(intersection_.at(size_t(k)).get());
  }
}

template <UnitKind K>
UnitModule* ModularPe::create_stage(int k) {
  if (k == 0)
    stage_dispatch_[size_t(K)] =
        std::make_unique<Dispatcher>((unit_name(K) + std::string("_dispatch")).c_str(),
                                     *rays_[size_t(inputs(K).front())], unit_count(K, ctx.config));
  stages_.push_back(std::make_unique<RayStageModule<K>>((unit_name(K) + std::to_string(k)).c_str(),
                                                        ctx, k, *stage_dispatch_[size_t(K)]));
  return stages_.back().get();
}

FifoMeter& ModularPe::meter(const FifoSpec& f, int lane) {
  if (f.per_lane) return intersection_[size_t(lane)]->root_fifo().meter();
  return f.payload == Payload::End ? ends_->meter() : rays_[size_t(f.id)]->meter();
}

FifoStatsList ModularPe::fifo_stats() {
  return rtm::fifo_stats(ctx, sc_core::sc_time_stamp().value(),
                         sc_core::sc_get_time_resolution().to_seconds(),
                         [&](const FifoSpec& f, int lane) -> FifoMeter& { return meter(f, lane); });
}

std::string ModularPe::occupancy_report() {
  return std::string(name()) + ": " +
         rtm::occupancy_report(
             ctx, front_->policy(),
             [&](const FifoSpec& f, int lane) -> FifoMeter& { return meter(f, lane); });
}

void ModularPe::trace(Waveform& wave) {
  for (const FifoSpec& f : fifo_table())
    if (f.payload == Payload::Ray && rays_[size_t(f.id)])
      rays_[size_t(f.id)]->trace(wave, std::string(rays_[size_t(f.id)]->name()) + ".occupancy",
                                 &ctx.window);
  ends_->trace(wave, std::string(ends_->name()) + ".occupancy", &ctx.window);
  front_->trace(wave);
  for (auto& s : stages_) s->trace(wave);
  for (auto& x : intersection_) x->trace(wave);
  shading_->trace(wave);
}

}  // namespace rtm
