#include "machine/search_unit.h"

#include "machine/routing.h"

namespace rtm {

SearchUnit::SearchUnit(sc_core::sc_module_name name, PeContext& ctx) : sc_module(name), ctx_(ctx), sleep_(ctx.sleeper()) {
  SC_THREAD(run);
}

void SearchUnit::run() {
  const MachineConfig& c = ctx_.config;
  for (;;) {
    MachineRay r = rays_in->read();
    probe_.begin(r.id);
    const Grid& g = *ctx_.image->grid;
    const bool walk_on = c.search_walk == MachineConfig::SearchWalk::UntilOccupied;
    uint64_t cycles = 0;
    Route route;
    for (;;) {
      const bool examined = search_pass(g, r);
      route = search_route(*ctx_.image->scene, g, r, examined);
      // Reading the voxel entry only happens when there is a voxel to examine.
      cycles += uint64_t(c.dda_step_cycles) + (examined ? uint64_t(c.voxel_read_cycles) : 0);
      if (examined) ++ctx_.counters.counts.voxel_steps;
      if (!(walk_on && route == Route::Feedback)) break;
    }
    ctx_.counters.search.busy_cycles += cycles;
    ++ctx_.counters.search.items;
    (*sleep_)(ctx_.cycles(cycles));
    switch (route) {
      case Route::Intersect: occupied_out->write(r); break;
      case Route::Feedback: feedback_out->write(r); break;
      case Route::Shade: shade_out->write(r); break;
      case Route::End: ends_out->write(RayEnd{r.id}); break;
    }
    probe_.end();
  }
}

}  // namespace rtm
