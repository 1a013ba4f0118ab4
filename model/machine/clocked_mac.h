// The MAC unit (paper §5.2, Fig. 2) on the PE clock: the clock-level datapath
// (units/clock_level_mac.h) as a SystemC process whose registers a waveform shows.
//
// Two implementations that agree exactly, in values and in cycles:
//  - MacTiming (units/mac_timing.h, the cycle model) + form_abg: the fast one, cycle counts by
//    formula, values by the schedule;
//  - ClockLevelMac: pipeline registers advanced edge by edge (the datapath of clocked timing: the
//    root unit takes its sums, and the fast model's must equal them).
#pragma once

#include <cstdint>
#include <string>

#include <systemc>

#include "machine/trace_window.h"
#include "machine/waveform.h"
#include "units/clock_level_mac.h"

namespace rtm {

/// The clock-level MAC on the PE clock: jobs posted at cycle boundaries stream through two
/// multipliers and the adder, a new job's products issuing while the previous job's drain, each
/// product in the cycle the schedule (MacTiming) gives it. The signals mirror the registers inside
/// the waveform window.
///
/// A process on the PE clock, but an SC_THREAD rather than an SC_CTHREAD: with no job inside it
/// waits for the next one instead of waking on every edge of the frame.
class ClockedMac : public sc_core::sc_module {
 public:
  sc_core::sc_in<bool> clk{"clk"};

  // Pipeline registers, visible in a waveform.
  sc_core::sc_signal<bool> m1_valid{"m1_valid"}, m2_valid{"m2_valid"}, add_valid{"add_valid"};
  sc_core::sc_signal<double> m1_a{"m1_a"}, m1_b{"m1_b"}, m1_out{"m1_out"};
  sc_core::sc_signal<double> m2_coef{"m2_coef"}, m2_out{"m2_out"};
  sc_core::sc_signal<double> acc{"acc"};
  sc_core::sc_signal<uint32_t> abg_select{
      "abg_select"};  ///< the sum the adder accumulates: 0 α, 1 β, 2 γ
  sc_core::sc_signal<uint32_t> product_counter{
      "product_counter"};  ///< products accumulated in the adder's job
  sc_core::sc_signal<uint32_t> adder_ray_id{"adder_ray_id"};  ///< the adder's job's ray ...
  sc_core::sc_signal<uint32_t> prim{"prim"};  ///< ... and primitive (its place in the voxel's list)
  sc_core::sc_signal<bool> sums_valid{
      "sums_valid"};  ///< a primitive's α, β, γ are handed on this cycle
  sc_core::sc_signal<double> alpha{"alpha"}, beta{"beta"}, gamma{"gamma"};

  SC_HAS_PROCESS(ClockedMac);
  ClockedMac(sc_core::sc_module_name name, const MacTiming& timing, Precision precision,
             sc_core::sc_time period);

  using Done = ClockLevelMac::Done;
  /// Posts a job at a cycle boundary: its cycle 0 is the next edge.
  void start(MacJob job);
  /// The oldest job, if its last sums are out (half a cycle before the cycle boundary after its
  /// last edge); false while it runs.
  bool finish(Done& done) { return mac_.finish(done); }
  /// While set, the result cannot be handed on: the whole pipeline holds, edge after edge.
  void stall(bool on) { stalled_ = on; }
  /// start(), wait until the job is done, finish(): for a caller with nothing else to do.
  Done run(MacJob job);

  /// Traces the pipeline registers; they change only inside the waveform window. The unit's busy
  /// flag and ray (UnitProbe) are traced beside them, under the same prefix.
  void trace(Waveform& wave, const std::string& prefix, const TraceWindow* window);

 private:
  void clocked();
  /// The registers' signals after an edge.
  void trace_edge(const ClockLevelMac::Registers& r);

  ClockLevelMac mac_;
  sc_core::sc_time period_;
  bool stalled_ = false;
  sc_core::sc_event posted_, finished_;
  const TraceWindow* window_ = nullptr;
};

}  // namespace rtm
