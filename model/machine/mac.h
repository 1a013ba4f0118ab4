// The MAC unit (paper §5.2, Fig. 2): two multipliers and an adder chained as a pipeline,
// accumulating 6 products for α, 12 for β and 10 for γ per primitive.
//
// Two implementations that agree exactly, in values and in cycles:
//  - MacTiming (units/mac_timing.h, the cycle model) + form_abg: the fast one, cycle counts by
//    formula, values by the schedule;
//  - ClockedMac: a process on the PE clock with pipeline registers as signals (for waveforms).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <systemc>

#include "machine/config.h"
#include "machine/trace_window.h"
#include "machine/waveform.h"
#include "units/mac_timing.h"

namespace rtm {

/// Rounds a double to the machine's precision. Computing a float operation in double and
/// rounding once gives exactly the IEEE float result for +, − and × (53 >= 2·24 + 2), so the
/// clocked MAC can hold its registers as doubles.
inline double round_to(Precision p, double x) { return p == Precision::Fp32 ? double(float(x)) : x; }

/// A MAC job in the clocked unit's terms: latches and one RAM image per primitive, already
/// rounded to the machine precision.
struct MacJob {
  std::vector<Latches<double>> latches;  ///< per primitive (the origin is re-centred on each)
  std::vector<CoefRam<double>> rams;
  std::vector<MacOps> ops;               ///< per primitive; empty: the full schedule for all
  uint32_t ray_id = 0;
};

class ClockedMac : public sc_core::sc_module {
 public:
  sc_core::sc_in<bool> clk{"clk"};

  // Pipeline registers, visible in a waveform.
  sc_core::sc_signal<bool> m1_valid{"m1_valid"}, m2_valid{"m2_valid"}, add_valid{"add_valid"};
  sc_core::sc_signal<double> m1_a{"m1_a"}, m1_b{"m1_b"}, m1_out{"m1_out"};
  sc_core::sc_signal<double> m2_coef{"m2_coef"}, m2_out{"m2_out"};
  sc_core::sc_signal<double> acc{"acc"};
  sc_core::sc_signal<uint32_t> product_counter{"product_counter"};  ///< products accumulated in this job
  sc_core::sc_signal<uint32_t> ray_id{"ray_id"};
  sc_core::sc_signal<bool> busy{"busy"};

  SC_HAS_PROCESS(ClockedMac);
  ClockedMac(sc_core::sc_module_name name, const MacTiming& timing, Precision precision, sc_core::sc_time period);

  /// Runs one job from the next clock edge; blocks the calling thread until the last sums are
  /// out. Returns α, β, γ per primitive and the cycles taken (the same as MacTiming's count).
  uint64_t run(const MacJob& job, std::vector<std::array<double, 3>>& sums);
  /// The same in two halves, for a caller that does its own waiting (arbitration = ranked):
  /// start() posts the job; finish(), called at the cycle boundary after the last edge or
  /// later, returns the cycles taken, or 0 if the job is still running.
  void start(const MacJob& job, std::vector<std::array<double, 3>>& sums);
  uint64_t finish();

  /// Traces the pipeline registers; they change only inside the waveform window.
  void trace(Waveform& wave, const std::string& prefix, const TraceWindow* window);

 private:
  void clocked();

  /// A product on its way down the pipeline.
  struct Stage {
    bool valid = false;
    int prim = 0;
    int k = 0;          ///< index into kMacSchedule
    bool last = false;  ///< the primitive's last product
    double value = 0;   ///< the product so far
  };

  MacTiming timing_;
  Precision precision_;
  sc_core::sc_time period_;
  const MacJob* job_ = nullptr;
  std::vector<std::array<double, 3>>* sums_ = nullptr;
  uint64_t cycles_ = 0;
  bool finished_ = false;
  sc_core::sc_event start_, done_;
  const TraceWindow* window_ = nullptr;
};

}  // namespace rtm
