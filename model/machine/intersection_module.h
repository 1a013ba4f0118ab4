// An intersection unit (paper §5) as a module: a MAC thread and a root-unit thread joined by
// the unit's own root_fifo, so the root unit and sort of one voxel overlap the MAC work of the
// next, as the paper's pipelining intends. The work is units/intersection.h's.
#pragma once

#include <memory>
#include <vector>

#include <systemc>

#include "machine/mac.h"
#include "machine/unit_module.h"
#include "units/intersection.h"

namespace rtm {

/// With several intersection units: wakes the lowest-numbered idle one for each ray that arrives
/// (units/intersection.h's LaneDispatcher), instead of leaving it to the kernel's wake-up order.
class LaneDispatchModule : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(LaneDispatchModule);
  LaneDispatchModule(sc_core::sc_module_name name, MeteredFifo<MachineRay>& in, int lanes);
  /// Unit `lane` found the FIFO empty: returns once a ray has been handed to it.
  void wait_for_ray(int lane);

 private:
  void dispatch();

  MeteredFifo<MachineRay>& in_;
  LaneDispatcher lanes_;
  std::vector<std::unique_ptr<sc_core::sc_event>> wake_;
};

class IntersectionModule : public UnitModule {
 public:
  SC_HAS_PROCESS(IntersectionModule);
  /// With a clock (clocked timing), every MAC job runs on a clock-level MAC unit and is checked
  /// against the schedule; without one, the fast model times it by formula.
  /// `lanes`: the dispatcher shared by several units, or null for the only one; `lane`: its number.
  IntersectionModule(sc_core::sc_module_name name, PeContext& ctx, sc_core::sc_clock* clock,
                     LaneDispatchModule* lanes, int lane);

  void trace(Waveform& wave);
  MeteredFifo<MacResult>& root_fifo() { return root_fifo_; }

 private:
  void mac_thread();
  void root_thread();

  MacUnit mac_;
  RootUnit root_;
  std::unique_ptr<Sleeper> mac_sleep_, root_sleep_;
  std::unique_ptr<ClockedMac> clocked_;  ///< null in fast timing
  LaneDispatchModule* lanes_;
  MeteredFifo<MacResult> root_fifo_;
  UnitProbe mac_probe_, root_probe_;
};

}  // namespace rtm
