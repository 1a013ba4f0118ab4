#include "machine/search_unit.h"

namespace rtm {

ExitRoute route_exit(const Scene& s, MachineRay& r) {
  if (r.ray.kind == RayKind::Shadow) {
    r.arrival = MachineRay::Arrival::LightReached;
    return ExitRoute::Shade;
  }
  if (r.ray.kind == RayKind::Primary) r.prim = ~0u;
  r.arrival = MachineRay::Arrival::Missed;
  const bool background = s.background != Vec3(0, 0, 0);
  return background ? ExitRoute::Shade : ExitRoute::End;
}

SearchUnit::SearchUnit(sc_core::sc_module_name name, PeContext& ctx) : sc_module(name), ctx_(ctx) { SC_THREAD(run); }

void SearchUnit::run() {
  const MachineConfig& c = ctx_.config;
  for (;;) {
    MachineRay r = rays_in->read();
    probe_.begin(r.id);
    const Grid& g = *ctx_.image->grid;
    const Ray& ray = r.ray;
    if (!r.started) {
      r.walk = Dda::start(g, ray.origin, ray.dir, 0.0, ray.t_max);
      r.started = true;
    }
    uint64_t cycles = c.dda_step_cycles;
    enum { Occupied, Empty, Exit } route = Exit;
    if (!r.walk.done) {
      // Examine the current voxel, then step to the next one.
      cycles += c.voxel_read_cycles;
      r.examined = r.walk;
      r.last = Dda::is_last(g, ray.dir, ray.t_max, r.walk);
      const bool occupied = g.count(g.index(r.walk.cell[0], r.walk.cell[1], r.walk.cell[2])) > 0;
      Dda::advance(g, ray.origin, ray.dir, ray.t_max, r.walk);
      ++ctx_.counters.counts.voxel_steps;
      route = occupied ? Occupied : (r.last ? Exit : Empty);
    }
    ctx_.counters.search.busy_cycles += cycles;
    ++ctx_.counters.search.items;
    sc_core::wait(ctx_.cycles(cycles));
    switch (route) {
      case Occupied: occupied_out->write(r); break;
      case Empty: feedback_out->write(r); break;
      case Exit:
        if (route_exit(*ctx_.image->scene, r) == ExitRoute::Shade)
          shade_out->write(r);
        else
          ends_out->write(RayEnd{r.id});
        break;
    }
    probe_.end();
  }
}

}  // namespace rtm
