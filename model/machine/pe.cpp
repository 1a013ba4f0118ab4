#include "machine/pe.h"

#include <sstream>

namespace rtm {
namespace {
PeContext make_context(int index, const MachineConfig& c, const PeUnits& units, Timekeeper* keeper) {
  PeContext ctx;
  ctx.keeper = keeper;
  ctx.pe = index;
  ctx.units = units;
  ctx.config = c;
  ctx.cycle = sc_core::sc_time(c.clock_ns, sc_core::SC_NS);
  return ctx;
}
}  // namespace

PeBase::PeBase(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units, size_t pixels,
               Timekeeper* keeper)
    : sc_module(name), ctx(make_context(index, c, units, keeper)), memory("memory", ctx, pixels) {
  memory.rays_expected = pixels;
}

Pe::Pe(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units, size_t pixels,
       sc_core::sc_clock* clock, Timekeeper* keeper)
    : PeBase(name, index, c, units, pixels, keeper),
      search_fifo("search_fifo", c.search_fifo_depth, "search"),
      intersect_fifo("intersect_fifo", c.intersect_fifo_depth, "intersect"),
      shade_fifo("shade_fifo", c.shade_fifo_depth, "shade"),
      feedback_search("feedback_search", c.feedback_fifo_depth, "feedback"),
      feedback_intersect("feedback_intersect", c.feedback_fifo_depth, "feedback"),
      ends_fifo("ends_fifo", c.feedback_fifo_depth, "ends"),
      front("front_buffer", ctx, memory, finished_event),
      shading("shading", ctx, memory) {
  front.from_search(feedback_search);
  front.from_intersect(feedback_intersect);
  if (units.spawn_path) {
    spawn_fifo = std::make_unique<MeteredFifo<MachineRay>>("spawn_fifo", c.feedback_fifo_depth, "spawn");
    front.from_shade(*spawn_fifo);
    shading.spawn_out(*spawn_fifo);
  }
  front.ends_in(ends_fifo);
  front.rays_out(search_fifo);

  for (int k = 0; k < c.search_units; ++k) {
    search.push_back(std::make_unique<SearchUnit>(("search" + std::to_string(k)).c_str(), ctx));
    SearchUnit& s = *search.back();
    s.rays_in(search_fifo);
    s.occupied_out(intersect_fifo);
    s.feedback_out(feedback_search);
    s.shade_out(shade_fifo);
    s.ends_out(ends_fifo);
  }

  if (c.intersection_units > 1)
    lanes = std::make_unique<LaneDispatcher>("lane_dispatcher", intersect_fifo, c.intersection_units);
  for (int k = 0; k < c.intersection_units; ++k) {
    intersection.push_back(std::make_unique<IntersectionStage>(("intersection" + std::to_string(k)).c_str(), ctx,
                                                               c.timing == Timing::Clocked ? clock : nullptr,
                                                               lanes.get(), k));
    IntersectionStage& x = *intersection.back();
    x.rays_in(intersect_fifo);
    x.hits_out(shade_fifo);
    x.feedback_out(feedback_intersect);
    x.ends_out(ends_fifo);
  }

  shading.rays_in(shade_fifo);
  shading.ends_out(ends_fifo);
}

template <class T>
std::vector<MeteredFifo<T>*> Pe::fifos_of() {
  if constexpr (std::is_same_v<T, RayEnd>)
    return {&ends_fifo};
  else
  {
    std::vector<MeteredFifo<MachineRay>*> f{&search_fifo, &intersect_fifo, &shade_fifo, &feedback_search,
                                            &feedback_intersect};
    if (spawn_fifo) f.push_back(spawn_fifo.get());
    return f;
  }
}

std::vector<std::pair<std::string, const FifoStats*>> Pe::fifo_stats() {
  std::vector<std::pair<std::string, const FifoStats*>> out;
  for (auto* f : fifos_of<MachineRay>()) out.emplace_back(f->basename(), &f->stats());
  for (auto& x : intersection) out.emplace_back(x->root_fifo().basename(), &x->root_fifo().stats());
  for (auto* f : fifos_of<RayEnd>()) out.emplace_back(f->basename(), &f->stats());
  return out;
}

std::string Pe::occupancy_report() {
  std::ostringstream s;
  s << name() << ": " << front.waiting() << " rays waiting in the front buffer, " << front.in_flight()
    << " past it;";
  for (auto* f : fifos_of<MachineRay>()) s << " " << f->basename() << " " << f->occupancy() << "/" << f->stats().depth;
  for (auto& x : intersection) s << " to_root " << x->root_fifo().occupancy() << "/" << ctx.config.root_fifo_depth;
  for (auto* f : fifos_of<RayEnd>()) s << " " << f->basename() << " " << f->occupancy() << "/" << f->stats().depth;
  return s.str();
}

void Pe::trace(sc_core::sc_trace_file* tf) {
  const std::string p = name();
  for (auto* f : fifos_of<MachineRay>()) f->trace(tf, p + "." + f->basename() + ".occupancy", &ctx.window);
  ends_fifo.trace(tf, p + ".ends_fifo.occupancy", &ctx.window);
  front.trace(tf, p + ".front_buffer");
  for (auto& s : search) s->trace(tf, std::string(s->name()));
  for (auto& x : intersection) x->trace(tf, std::string(x->name()));
  shading.trace(tf, p + ".shading");
}

}  // namespace rtm
