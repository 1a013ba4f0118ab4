// The MAC unit (paper §5.2, Fig. 2): two multipliers and an adder chained as a pipeline,
// accumulating 6 products for α, 12 for β and 10 for γ per primitive.
//
// Two implementations that agree exactly, in values and in cycles:
//  - MacTiming (units/mac_timing.h, the cycle model) + form_abg: the fast one, cycle counts by
//    formula, values by the schedule;
//  - ClockedMac: a process on the PE clock with pipeline registers (the datapath of clocked
//    timing: the root unit takes its sums, and the fast model's must equal them).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include <systemc>

#include "config/config.h"
#include "machine/trace_window.h"
#include "machine/waveform.h"
#include "units/mac_timing.h"

namespace rtm {

/// Rounds a double to the machine's precision. Computing a float operation in double and
/// rounding once gives exactly the IEEE float result for +, − and × (53 >= 2·24 + 2), so the
/// clocked MAC can hold its registers as doubles.
inline double round_to(Precision p, double x) {
  return p == Precision::Fp32 ? double(float(x)) : x;
}

/// A MAC job in the clocked unit's terms: latches and one RAM image per primitive, already
/// rounded to the machine precision.
struct MacJob {
  std::vector<Latches<double>> latches;  ///< per primitive (the origin is re-centred on each)
  std::vector<CoefRam<double>> rams;
  std::vector<MacOps> ops;  ///< per primitive; empty: the full schedule for all
  std::vector<uint64_t>
      loads;  ///< per primitive, cycles to load its coefficients (MacTiming::Job::loads)
  uint32_t ray_id = 0;
};

/// The clocked MAC (Fig. 2) as the datapath of clocked timing: jobs posted at cycle boundaries
/// stream through two multipliers and the adder, a new job's products issuing while the previous
/// job's drain, each product in the cycle the schedule (MacTiming) gives it. The registers are
/// the process's state on every edge it runs; the signals mirror them inside the waveform window.
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

  /// A finished job: α, β, γ per primitive and its cycles from its first edge to its last.
  struct Done {
    std::vector<std::array<double, 3>> sums;
    uint64_t cycles = 0;
  };
  /// Posts a job at a cycle boundary: its cycle 0 is the next edge.
  void start(MacJob job);
  /// The oldest job, if its last sums are out (half a cycle before the cycle boundary after its
  /// last edge); false while it runs.
  bool finish(Done& done);
  /// While set, the result cannot be handed on: the whole pipeline holds, edge after edge.
  void stall(bool on) { stalled_ = on; }
  /// start(), wait until the job is done, finish(): for a caller with nothing else to do.
  Done run(MacJob job);

  /// Traces the pipeline registers; they change only inside the waveform window. The unit's busy
  /// flag and ray (UnitProbe) are traced beside them, under the same prefix.
  void trace(Waveform& wave, const std::string& prefix, const TraceWindow* window);

 private:
  void clocked();
  void edge();
  bool idle() const;

  /// A product on its way down the pipeline.
  struct Stage {
    bool valid = false;
    uint64_t job = 0;  ///< its job's serial number
    int prim = 0;
    int k = 0;          ///< index into kMacSchedule
    bool last = false;  ///< the primitive's last product
    double value = 0;   ///< the product so far
  };
  struct Posted {
    MacJob job;
    MacTiming::Job plan;
    uint64_t start = 0;   ///< the tick of its cycle 0
    int prim = 0, j = 0;  ///< its next product to issue
    Done done;
    bool finished = false;
  };
  Posted& job(uint64_t serial) { return jobs_[size_t(serial - first_serial_)]; }

  // The stages of one edge, in the order edge() runs them.
  /// The adder: the product leaving it into α, β or γ; true when a primitive's sums are handed.
  bool accumulate(bool tracing);
  /// Multiplier 2: the product from multiplier 1 times its coefficient, into the adder.
  Stage multiply_by_coefficient();
  /// Multiplier 1: the product of two latches, into multiplier 2.
  Stage multiply_latches();
  /// The product the schedule issues at this edge (invalid: none), for multiplier 1.
  Stage issue();
  /// The registers' signals after the edge.
  void trace_edge(const Stage& in, const Stage& m1, const Stage& m2, bool handed);

  MacTiming timing_;
  Precision precision_;
  sc_core::sc_time period_;
  std::deque<Posted> jobs_;  ///< posted and not yet handed on, oldest first
  uint64_t first_serial_ = 0;
  uint64_t tick_ = 0;  ///< edges run so far (held edges do not count)
  std::deque<Stage> mul1_, mul2_, adder_;
  double sum_[3] = {0, 0, 0};
  uint32_t accumulated_ = 0;
  bool stalled_ = false;
  sc_core::sc_event posted_, finished_;
  const TraceWindow* window_ = nullptr;
};

}  // namespace rtm
