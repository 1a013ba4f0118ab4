// The MAC unit's cycle model (paper §5.2, Fig. 2), by formula: when each product issues and when
// each primitive's α, β, γ leave the adder. The clock-level MAC (ClockLevelMac) runs the same
// schedule edge by edge (units/clock_level_mac.h) and must agree with it exactly.
//
// Products issue in schedule order, one every add_latency cycles (each add depends on the
// previous one, so a longer adder cannot accept a product every cycle). A primitive's coefficients
// that are not in the MAC's RAM are loaded while the previous primitive runs, so primitive p + 1
// starts max(n_p · add_latency, load_{p+1}) after primitive p, the first after load_0. The loads
// are a job's own (Job::loads: a coefficient RAM miss takes the local memory's time, a hit none);
// without them every primitive loads in coef_load_cycles (the uniform schedule the clocked MAC's
// tests use). A product spends mul_latency cycles in each multiplier and add_latency in the adder.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "geom/mac_schedule.h"
#include "config/config.h"

namespace rtm {

struct MacTiming {
  int mul_latency = 1, add_latency = 1, coef_load_cycles = 0;

  /// The machine's MAC; its loads are each job's own (a coefficient RAM miss's local-memory time).
  explicit MacTiming(const MachineConfig& c)
      : mul_latency(c.mul_latency), add_latency(c.add_latency) {}
  MacTiming(int mul, int add, int load)
      : mul_latency(mul), add_latency(add), coef_load_cycles(load) {}

  uint64_t period() const {
    return std::max<uint64_t>(uint64_t(kMacProducts) * add_latency, coef_load_cycles);
  }
  /// Cycle (from the job's start) in which product j of primitive p issues into multiplier 1.
  uint64_t issue(int p, int j) const {
    return coef_load_cycles + uint64_t(p) * period() + uint64_t(j) * add_latency;
  }
  /// The cycle in which primitive p's α, β, γ leave the adder (its last product latched into
  /// multiplier 1 at cycle issue, into multiplier 2 mul_latency later, and so on).
  uint64_t done(int p) const { return issue(p, kMacProducts - 1) + 2 * mul_latency + add_latency; }
  /// Cycles the MAC is busy with a voxel of n primitives: cycles 0 .. done(n − 1).
  uint64_t job_cycles(int n) const { return n == 0 ? 0 : done(n - 1) + 1; }

  /// The same rules for a job whose primitives run counts[p] products each (sparse schedules).
  struct Job {
    std::vector<uint64_t> start;  ///< cycle of each primitive's first product
    std::vector<int> counts;
    std::vector<uint64_t>
        loads;  ///< cycles to load each primitive's coefficients; empty: coef_load_cycles each
    int add_latency = 1, pipe = 3;  ///< pipe: 2 · mul_latency + add_latency
    uint64_t next_load = 0;         ///< the load a next job's first primitive is assumed to take

    uint64_t issue(int p, int j) const { return start[size_t(p)] + uint64_t(j) * add_latency; }
    uint64_t done(int p) const { return issue(p, counts[size_t(p)] - 1) + pipe; }
    uint64_t cycles() const { return counts.empty() ? 0 : done(int(counts.size()) - 1) + 1; }
    /// Cycles from the job's start until a next job, started then, issues its first product no
    /// earlier than right after this job's last primitive's slot. Uniform loads: the job's issue
    /// slots without its first load (the next job's first load, as long, overlaps this job's end);
    /// a job's own loads: its issue slots with them (the next job's first load may be shorter).
    uint64_t issue_span() const {
      if (counts.empty()) return 0;
      const size_t last = counts.size() - 1;
      return start[last] + std::max<uint64_t>(uint64_t(counts[last]) * add_latency, next_load) -
             (loads.empty() ? start[0] : 0);
    }
  };
  Job job(const std::vector<int>& counts, const std::vector<uint64_t>& loads = {}) const {
    Job j;
    j.counts = counts;
    j.loads = loads;
    plan(j);
    return j;
  }
  /// Fills in j's schedule for the counts and loads it holds (reusing its storage).
  void plan(Job& j) const {
    j.add_latency = add_latency;
    j.pipe = 2 * mul_latency + add_latency;
    j.next_load = j.loads.empty() ? uint64_t(coef_load_cycles) : 0;
    auto load = [&](size_t p) {
      return j.loads.empty() ? uint64_t(coef_load_cycles) : p < j.loads.size() ? j.loads[p] : 0;
    };
    j.start.clear();
    uint64_t at = load(0);
    for (size_t p = 0; p < j.counts.size(); ++p) {
      j.start.push_back(at);
      at += std::max<uint64_t>(uint64_t(j.counts[p]) * add_latency,
                               p + 1 < j.counts.size() ? load(p + 1) : j.next_load);
    }
  }
};

}  // namespace rtm
