// A unit that exists only in the test of docs/architecture.md, "Adding a unit": a stage between
// the search and the intersection units that holds each ray it takes for a few cycles and hands
// it on unchanged. It joins the machine through the tables alone (pass_through.def), as a ray
// stage (units/ray_stage.h), so both schedulers run it with the operations they run the search
// units with.
#pragma once

#include "units/output.h"  // and, through units/extra_units.h, pass_through.def

namespace rtm {

class PassThroughUnit {
 public:
  static constexpr uint64_t kCycles = RTM_PASS_THROUGH_CYCLES;

  PassThroughUnit(PeState& pe, int index) : pe_(pe), index_(index) {}

  /// Holds ray `r`, taken at `now` (ticks), kCycles cycles, one ray entering a cycle.
  Work take(MachineRay& r, uint64_t now) {
    Work w;
    w.cycles = kCycles;
    w.interval = 1;
    w.out = {FifoId::Intersect, Output::What::Item};
    if (pe_.log) pe_.log->take(now, UnitKind::PassThrough, index_, r.id, w.cycles);
    return w;
  }

 private:
  PeState& pe_;
  int index_;
};

}  // namespace rtm
