#include "machine/modules_pe.h"

#include <set>
#include <sstream>

namespace rtm {
ModulesPe::ModulesPe(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units,
                     size_t pixels, sc_core::sc_clock* clock, Timekeeper* keeper)
    : Pe(name, index, c, units, pixels, keeper) {
  for (const FifoSpec& f : fifo_table()) {
    if (f.per_lane || !units.has(f)) continue;
    if (f.payload == Payload::Ray)
      rays_[size_t(f.id)] = std::make_unique<MeteredFifo<MachineRay>>(f.name, c.*f.depth, f.kind);
    else
      ends_ = std::make_unique<MeteredFifo<RayEnd>>(f.name, c.*f.depth, f.kind);
  }
  // In this order: the kernel's order among processes runnable together follows it
  // (arbitration = kernel).
  front_ = std::make_unique<FrontBufferModule>("front_buffer", ctx, memory, finished_event);
  shading_ = std::make_unique<ShadingModule>("shading", ctx, memory);
  search_dispatch_ = std::make_unique<Dispatcher>("search_dispatch", *rays_[size_t(FifoId::Search)], c.search_units);
  for (int k = 0; k < c.search_units; ++k)
    search_.push_back(
        std::make_unique<SearchModule>(("search" + std::to_string(k)).c_str(), ctx, k, *search_dispatch_));
  intersect_dispatch_ =
      std::make_unique<Dispatcher>("intersect_dispatch", *rays_[size_t(FifoId::Intersect)], c.intersection_units);
  for (int k = 0; k < c.intersection_units; ++k)
    intersection_.push_back(std::make_unique<IntersectionModule>(("intersection" + std::to_string(k)).c_str(), ctx,
                                                                 c.timing == Timing::Clocked ? clock : nullptr,
                                                                 *intersect_dispatch_, k));

  for (const FifoSpec& f : fifo_table()) {
    if (f.per_lane || !units.has(f)) continue;
    std::set<UnitModule*> ends;  // a module running several units binds each FIFO once
    for (const auto* kinds : {&f.writers, &f.readers})
      for (UnitKind k : *kinds)
        for (UnitModule* m : modules_of(k)) ends.insert(m);
    for (UnitModule* m : ends) {
      if (f.payload == Payload::Ray)
        m->bind(f.id, *rays_[size_t(f.id)]);
      else
        m->bind(f.id, *ends_);
    }
  }
}

std::vector<UnitModule*> ModulesPe::modules_of(UnitKind k) {
  switch (k) {
    case UnitKind::FrontBuffer: return {front_.get()};
    case UnitKind::Shading: return {shading_.get()};
    case UnitKind::Search: {
      std::vector<UnitModule*> v;
      for (auto& s : search_) v.push_back(s.get());
      return v;
    }
    case UnitKind::Mac:
    case UnitKind::Root: {
      std::vector<UnitModule*> v;
      for (auto& x : intersection_) v.push_back(x.get());
      return v;
    }
  }
  return {};
}

std::vector<std::pair<std::string, const FifoStats*>> ModulesPe::fifo_stats() {
  std::vector<std::pair<std::string, const FifoStats*>> out;
  for (const FifoSpec& f : fifo_table()) {
    if (f.per_lane)
      for (auto& x : intersection_) out.emplace_back(f.name, &x->root_fifo().stats());
    else if (f.payload == Payload::Ray && rays_[size_t(f.id)])
      out.emplace_back(f.name, &rays_[size_t(f.id)]->stats());
    else if (f.payload == Payload::End)
      out.emplace_back(f.name, &ends_->stats());
  }
  return out;
}

std::string ModulesPe::occupancy_report() {
  std::ostringstream s;
  s << name() << ": " << front_->policy().waiting() << " rays waiting in the front buffer, "
    << front_->policy().in_flight() << " past it;";
  for (const FifoSpec& f : fifo_table()) {
    if (f.per_lane)
      for (auto& x : intersection_) s << " " << f.name << " " << x->root_fifo().occupancy() << "/" << ctx.config.*f.depth;
    else if (f.payload == Payload::Ray && rays_[size_t(f.id)])
      s << " " << f.name << " " << rays_[size_t(f.id)]->occupancy() << "/" << ctx.config.*f.depth;
    else if (f.payload == Payload::End)
      s << " " << f.name << " " << ends_->occupancy() << "/" << ctx.config.*f.depth;
  }
  return s.str();
}

void ModulesPe::trace(Waveform& wave) {
  for (const FifoSpec& f : fifo_table())
    if (f.payload == Payload::Ray && rays_[size_t(f.id)])
      rays_[size_t(f.id)]->trace(wave, std::string(rays_[size_t(f.id)]->name()) + ".occupancy", &ctx.window);
  ends_->trace(wave, std::string(ends_->name()) + ".occupancy", &ctx.window);
  front_->trace(wave);
  for (auto& s : search_) s->trace(wave);
  for (auto& x : intersection_) x->trace(wave);
  shading_->trace(wave);
}

}  // namespace rtm
