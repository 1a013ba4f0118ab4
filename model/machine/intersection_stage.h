// The intersection stage (paper §5): the MAC unit forms α, β, γ for every primitive in the
// examined voxel; the root unit solves each quadratic, clip tests keep the bounded part, and
// the sort keeps the nearest hit inside the voxel. Two threads, so the root unit and sort of one
// voxel overlap the MAC work of the next, as the paper's pipelining intends.
#pragma once

#include <memory>
#include <set>
#include <vector>

#include <systemc>

#include "machine/mac.h"
#include "machine/machine_ray.h"
#include "machine/metered_fifo.h"
#include "machine/pe_context.h"
#include "machine/unit_work.h"

namespace rtm {

/// With several intersection units: hands each occupied-voxel ray that arrives to the idle unit
/// with the lowest number, so which unit takes a ray follows the numbering, not the order in
/// which SystemC wakes processes waiting on the same FIFO (the PE engine follows the same rule).
class LaneDispatcher : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(LaneDispatcher);
  LaneDispatcher(sc_core::sc_module_name name, MeteredFifo<MachineRay>& in, int lanes);
  /// Unit `lane` found the FIFO empty: returns once a ray has been handed to it.
  void wait_for_ray(int lane);

 private:
  void dispatch();

  MeteredFifo<MachineRay>& in_;
  std::set<int> idle_;
  std::vector<std::unique_ptr<sc_core::sc_event>> wake_;
};

class IntersectionStage : public sc_core::sc_module {
 public:
  sc_core::sc_fifo_in<MachineRay> rays_in{"rays_in"};             ///< occupied voxels, from the search units
  sc_core::sc_fifo_out<MachineRay> hits_out{"hits_out"};          ///< to shading
  sc_core::sc_fifo_out<MachineRay> feedback_out{"feedback_out"};  ///< no hit here: back to the front buffer
  sc_core::sc_fifo_out<RayEnd> ends_out{"ends_out"};              ///< blocked shadow rays; misses with nothing to add

  SC_HAS_PROCESS(IntersectionStage);
  /// With a clock (clocked timing), every MAC job runs on a clock-level MAC unit and is checked
  /// against the schedule; without one, the fast model times it by formula.
  /// `lanes`: the dispatcher shared by several units, or null for the only one; `lane`: its number.
  IntersectionStage(sc_core::sc_module_name name, PeContext& ctx, sc_core::sc_clock* clock, LaneDispatcher* lanes,
                    int lane);

  void trace(sc_core::sc_trace_file* tf, const std::string& prefix);
  MeteredFifo<MacResult>& root_fifo() { return to_root_; }

 private:
  void mac_thread();
  void root_thread();

  PeContext& ctx_;
  std::unique_ptr<Sleeper> mac_sleep_, root_sleep_;
  MacTiming timing_;
  std::unique_ptr<ClockedMac> clocked_;  ///< null in fast timing
  LaneDispatcher* lanes_;
  int lane_;
  MeteredFifo<MacResult> to_root_;
  UnitProbe mac_probe_, root_probe_;
};

}  // namespace rtm
