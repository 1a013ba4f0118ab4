#include "units/search_unit.h"

namespace rtm {

Work SearchUnit::take(MachineRay& r, uint64_t now) {
  const MachineConfig& c = pe_.config;
  const Grid& g = *pe_.image->grid;
  const bool walk_on = c.search_walk == MachineConfig::SearchWalk::UntilOccupied;
  const bool fp32 = c.dda_precision_in_force() == Precision::Fp32;
  Work w;
  Route route;
  uint64_t passes = 0;
  const uint64_t cycle = now / pe_.cycle;
  for (;;) {
    ++passes;
    const bool examined = fp32 ? search_pass<float>(g, r) : search_pass<double>(g, r);
    route = search_route(*pe_.image->scene, g, r, examined);
    w.cycles += uint64_t(c.dda_step_cycles);
    // Reading the voxel entry only happens when there is a voxel to examine. A walk of several
    // passes asks for all its entries when it is taken, each needed at the end of its pass.
    if (examined) {
      ++pe_.counters.counts.voxel_steps;
      if (PeMemory* m = pe_.memory.get()) {
        const int64_t v = g.index(r.examined.cell[0], r.examined.cell[1], r.examined.cell[2]);
        const PeMemory::VoxelRead entry =
            m->voxel_read(m->addresses().voxel_entry(v), voxel_entry_bytes());
        w.cycles += entry.cycles;
        w.wait.latency = w.cycles;  // so far: the latency its plan has when it is read
        if (entry.bytes)
          m->request(m->search(index_), entry.address, entry.bytes, cycle, w.cycles, w.wait);
      }
    }
    if (!(walk_on && route == Route::Feedback)) break;
  }
  w.wait.latency = w.cycles;
  w.interval = pipeline_interval(c.search_interval, w.cycles, passes);
  switch (route) {
    case Route::Intersect:
      w.out = {kSearchToIntersect, Output::What::Item};
      break;
    case Route::Feedback:
      w.out = {FifoId::FeedbackSearch, Output::What::Item};
      break;
    case Route::Shade:
      w.out = {FifoId::Shade, Output::What::Item};
      break;
    case Route::End:
      w.out = {FifoId::Ends, Output::What::End};
      break;
  }
  if (pe_.log) pe_.log->take(now, UnitKind::Search, index_, r.id, w.cycles);
  return w;
}

}  // namespace rtm
