// The MAC unit's cycle model (paper §5.2, Fig. 2), by formula: when each product issues and when
// each primitive's α, β, γ leave the adder. machine/mac.h's ClockedMac runs the same schedule on
// a clock and must agree with it exactly.
//
// Products issue in schedule order, one every add_latency cycles (each add depends on the
// previous one, so a longer adder cannot accept a product every cycle). A primitive's 13
// coefficient words are loaded into the RAM while the previous primitive runs, so a primitive
// starts every max(28 · add_latency, coef_load_cycles) cycles, the first after coef_load_cycles.
// A product spends mul_latency cycles in each multiplier and add_latency in the adder.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "geom/mac_schedule.h"
#include "machine/config.h"

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
    /// Cycles from the job's start until a next job, started then, would issue its first product
    /// right after this job's last primitive's slot: the job's issue slots, without its first load.
    uint64_t issue_span(int coef_load_cycles) const {
      if (counts.empty()) return 0;
      const size_t last = counts.size() - 1;
      return start[last] + std::max<uint64_t>(uint64_t(counts[last]) * add_latency, coef_load_cycles) - coef_load_cycles;
    }
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

}  // namespace rtm
