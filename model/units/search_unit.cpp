#include "units/search_unit.h"

namespace rtm {

Work SearchUnit::take(MachineRay& r, uint64_t now) {
  const MachineConfig& c = pe_.config;
  const Grid& g = *pe_.image->grid;
  const bool walk_on = c.search_walk == MachineConfig::SearchWalk::UntilOccupied;
  Work w;
  Route route;
  uint64_t passes = 0;
  for (;;) {
    ++passes;
    const bool examined = search_pass(g, r);
    route = search_route(*pe_.image->scene, g, r, examined);
    // Reading the voxel entry only happens when there is a voxel to examine.
    w.cycles += uint64_t(c.dda_step_cycles) + (examined ? uint64_t(c.voxel_read_cycles) : 0);
    if (examined) ++pe_.counters.counts.voxel_steps;
    if (!(walk_on && route == Route::Feedback)) break;
  }
  w.interval = pipeline_interval(c.search_interval, w.cycles, passes);
  switch (route) {
    case Route::Intersect: w.out = {FifoId::Intersect, Output::What::Item}; break;
    case Route::Feedback: w.out = {FifoId::FeedbackSearch, Output::What::Item}; break;
    case Route::Shade: w.out = {FifoId::Shade, Output::What::Item}; break;
    case Route::End: w.out = {FifoId::Ends, Output::What::End}; break;
  }
  if (pe_.log) pe_.log->take(now, UnitKind::Search, index_, r.id, w.cycles);
  return w;
}

}  // namespace rtm
