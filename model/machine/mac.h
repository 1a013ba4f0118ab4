// The MAC unit (paper §5.2, Fig. 2): two multipliers and an adder chained as a pipeline,
// accumulating 6 products for α, 12 for β and 10 for γ per primitive.
//
// Two implementations that agree exactly, in values and in cycles:
//  - MacTiming + form_abg: the fast one, cycle counts by formula, values by the schedule;
//  - ClockedMac: a process on the PE clock with pipeline registers as signals (for waveforms).
//
// Cycle model. Products issue in schedule order, one every add_latency cycles (each add depends
// on the previous one, so a longer adder cannot accept a product every cycle). A primitive's 13
// coefficient words are loaded into the RAM while the previous primitive runs, so a primitive
// starts every max(28 · add_latency, coef_load_cycles) cycles, the first after coef_load_cycles.
// A product spends mul_latency cycles in each multiplier and add_latency in the adder.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <systemc>

#include "geom/mac_schedule.h"
#include "machine/config.h"
#include "machine/trace_window.h"

namespace rtm {

struct MacTiming {
  int mul_latency = 1, add_latency = 1, coef_load_cycles = 0;

  explicit MacTiming(const MachineConfig& c)
      : mul_latency(c.mul_latency), add_latency(c.add_latency), coef_load_cycles(c.coef_load_cycles) {}
  MacTiming(int mul, int add, int load) : mul_latency(mul), add_latency(add), coef_load_cycles(load) {}

  uint64_t period() const { return std::max<uint64_t>(uint64_t(kMacProducts) * add_latency, coef_load_cycles); }
  /// Cycle (from the job's start) in which product j of primitive p issues into multiplier 1.
  uint64_t issue(int p, int j) const { return coef_load_cycles + uint64_t(p) * period() + uint64_t(j) * add_latency; }
  /// The cycle in which primitive p's α, β, γ leave the adder (its last product latched into
  /// multiplier 1 at cycle issue, into multiplier 2 mul_latency later, and so on).
  uint64_t done(int p) const { return issue(p, kMacProducts - 1) + 2 * mul_latency + add_latency; }
  /// Cycles the MAC is busy with a voxel of n primitives: cycles 0 .. done(n − 1).
  uint64_t job_cycles(int n) const { return n == 0 ? 0 : done(n - 1) + 1; }

  /// The same rules for a job whose primitives run counts[p] products each (sparse schedules).
  struct Job {
    std::vector<uint64_t> start;  ///< cycle of each primitive's first product
    std::vector<int> counts;
    int add_latency = 1, pipe = 3;  ///< pipe: 2 · mul_latency + add_latency

    uint64_t issue(int p, int j) const { return start[size_t(p)] + uint64_t(j) * add_latency; }
    uint64_t done(int p) const { return issue(p, counts[size_t(p)] - 1) + pipe; }
    uint64_t cycles() const { return counts.empty() ? 0 : done(int(counts.size()) - 1) + 1; }
  };
  Job job(const std::vector<int>& counts) const {
    Job j;
    j.counts = counts;
    plan(j);
    return j;
  }
  /// Fills in j's schedule for the counts it holds (reusing its storage).
  void plan(Job& j) const {
    j.add_latency = add_latency;
    j.pipe = 2 * mul_latency + add_latency;
    j.start.clear();
    uint64_t at = coef_load_cycles;
    for (int n : j.counts) {
      j.start.push_back(at);
      at += std::max<uint64_t>(uint64_t(n) * add_latency, coef_load_cycles);
    }
  }
};

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
  void trace(sc_core::sc_trace_file* tf, const std::string& prefix, const TraceWindow* window);

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
