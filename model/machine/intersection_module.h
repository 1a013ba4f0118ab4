// An intersection unit (paper §5) as a module: a MAC thread and a root-unit thread joined by
// the unit's own root_fifo, so the root unit and sort of one voxel overlap the MAC work of the
// next, as the paper's pipelining intends. The work is units/intersection.h's.
#pragma once

#include <deque>
#include <memory>
#include <vector>

#include <systemc>

#include "machine/clocked_mac.h"
#include "machine/unit_module.h"
#include "units/intersection.h"

namespace rtm {

class IntersectionModule : public UnitModule {
 public:
  SC_HAS_PROCESS(IntersectionModule);
  /// With a clock (clocked timing), every MAC job runs on a clock-level MAC unit and is checked
  /// against the schedule; without one, the fast model times it by formula. `dispatcher` hands
  /// the intersection units their rays; `lane`: this one's number.
  IntersectionModule(sc_core::sc_module_name name, PeContext& ctx, sc_core::sc_clock* clock,
                     Dispatcher& dispatcher, int lane);

  void trace(Waveform& wave) override;
  MeteredFifo<MacResult>& root_fifo() { return root_fifo_; }

 private:
  struct Held {
    MacResult m;
    Output out;
  };
  struct MacOps;
  struct RootOps;
  void mac_thread();
  void root_thread();

  MacUnit mac_;
  RootUnit root_;
  std::unique_ptr<Sleeper> mac_sleep_, root_sleep_;
  std::unique_ptr<ClockedMac> clocked_;  ///< null in fast timing
  std::deque<uint64_t> job_cycles_;      ///< the fast model's cycles of each job in the clocked MAC
  Dispatcher& dispatcher_;
  MeteredFifo<MacResult> root_fifo_;
  Pipeline<Held> mac_pipe_, root_pipe_;
  UnitProbe mac_probe_, root_probe_;
};

}  // namespace rtm
