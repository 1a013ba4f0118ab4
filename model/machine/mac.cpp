#include "machine/mac.h"

#include <deque>

namespace rtm {

using sc_core::sc_time;

ClockedMac::ClockedMac(sc_core::sc_module_name name, const MacTiming& timing, Precision precision, sc_time period)
    : sc_module(name), timing_(timing), precision_(precision), period_(period) {
  SC_THREAD(clocked);
}

uint64_t ClockedMac::run(const MacJob& job, std::vector<std::array<double, 3>>& sums) {
  start(job, sums);
  sc_core::wait(done_);
  return finish();
}

void ClockedMac::start(const MacJob& job, std::vector<std::array<double, 3>>& sums) {
  job_ = &job;
  sums_ = &sums;
  sums.assign(job.rams.size(), {0, 0, 0});
  finished_ = false;
  start_.notify();
}

uint64_t ClockedMac::finish() {
  if (!finished_) return 0;
  job_ = nullptr;
  return cycles_;
}

void ClockedMac::clocked() {
  const Precision p = precision_;
  for (;;) {
    sc_core::wait(start_);
    // The clock's rising edges fall mid-cycle (see Machine): cycle 0's edge is the first after
    // the job was posted at a cycle boundary.
    sc_core::wait(clk.posedge_event());
    const MacJob& job = *job_;
    const int prims = int(job.rams.size());
    // The products in issue order, with the cycle each issues in.
    std::vector<int> counts;
    for (int p = 0; p < prims; ++p) counts.push_back(job.ops.empty() ? kMacProducts : int(job.ops[size_t(p)].size()));
    const MacTiming::Job plan = timing_.job(counts);
    struct Issue {
      int prim, k, j;
    };
    std::vector<Issue> order;
    for (int p = 0; p < prims; ++p)
      for (int j = 0; j < counts[size_t(p)]; ++j) order.push_back({p, job.ops.empty() ? j : job.ops[size_t(p)][size_t(j)], j});
    const int total = int(order.size());
    const uint64_t end = plan.cycles();

    // Each multiplier and the adder is a shift register as long as its latency; every edge,
    // each entry moves one place and the one leaving a unit has that unit's operation applied.
    std::deque<Stage> mul1(size_t(timing_.mul_latency)), mul2(size_t(timing_.mul_latency)),
        adder(size_t(timing_.add_latency));
    double sum[3] = {0, 0, 0};
    int issued = 0, accumulated = 0;
    double last_acc = 0;
    bool tracing = window_ && window_->now();
    if (tracing) busy.write(true), ray_id.write(job.ray_id);

    for (uint64_t cycle = 0; cycle < end; ++cycle) {
      // Adder: accumulate the product leaving it into α, β or γ.
      const Stage out = adder.back();
      adder.pop_back();
      if (out.valid) {
        const MacOp& op = kMacSchedule[size_t(out.k)];
        sum[op.sum] = round_to(p, sum[op.sum] + out.value);
        last_acc = sum[op.sum];
        ++accumulated;
        if (out.last) {
          (*sums_)[size_t(out.prim)] = {sum[0], sum[1], sum[2]};
          sum[0] = sum[1] = sum[2] = 0;
        }
      }
      // Multiplier 2: multiplier 1's product times the coefficient RAM word.
      Stage m2 = mul2.back();
      mul2.pop_back();
      if (m2.valid) m2.value = round_to(p, m2.value * job.rams[size_t(m2.prim)][kMacSchedule[size_t(m2.k)].w]);
      adder.push_front(m2);
      // Multiplier 1: two latch operands.
      Stage m1 = mul1.back();
      mul1.pop_back();
      if (m1.valid) {
        const MacOp& op = kMacSchedule[size_t(m1.k)];
        m1.value = round_to(p, job.latches[size_t(m1.prim)][op.x] * job.latches[size_t(m1.prim)][op.y]);
      }
      mul2.push_front(m1);
      // Issue the next product when the schedule says so.
      Stage in;
      if (issued < total && cycle == plan.issue(order[size_t(issued)].prim, order[size_t(issued)].j)) {
        const Issue& next = order[size_t(issued)];
        in.valid = true;
        in.prim = next.prim;
        in.k = next.k;
        in.last = next.j == counts[size_t(next.prim)] - 1;
        ++issued;
      }
      mul1.push_front(in);

      tracing = window_ && window_->now();
      if (tracing) {
        m1_valid.write(in.valid);
        if (in.valid) {
          const MacOp& op = kMacSchedule[size_t(in.k)];
          m1_a.write(job.latches[size_t(in.prim)][op.x]);
          m1_b.write(job.latches[size_t(in.prim)][op.y]);
        }
        if (m1.valid) m1_out.write(m1.value), m2_coef.write(job.rams[size_t(m1.prim)][kMacSchedule[size_t(m1.k)].w]);
        m2_valid.write(m1.valid);
        if (m2.valid) m2_out.write(m2.value);
        add_valid.write(m2.valid);
        if (out.valid) acc.write(last_acc);
        product_counter.write(uint32_t(accumulated));
      }
      if (cycle + 1 < end) sc_core::wait(clk.posedge_event());
    }
    if (tracing) busy.write(false), m1_valid.write(false), m2_valid.write(false), add_valid.write(false);
    cycles_ = end;
    finished_ = true;
    // The sums are in the accumulator at this edge; the stage takes them at the next cycle boundary.
    done_.notify(period_ / 2);
  }
}

void ClockedMac::trace(Waveform& wave, const std::string& prefix, const TraceWindow* window) {
  window_ = window;
  wave.trace(busy, prefix + ".busy");
  wave.trace(ray_id, prefix + ".ray_id");
  wave.trace(m1_valid, prefix + ".m1_valid");
  wave.trace(m1_a, prefix + ".m1_a");
  wave.trace(m1_b, prefix + ".m1_b");
  wave.trace(m1_out, prefix + ".m1_out");
  wave.trace(m2_valid, prefix + ".m2_valid");
  wave.trace(m2_coef, prefix + ".m2_coef");
  wave.trace(m2_out, prefix + ".m2_out");
  wave.trace(add_valid, prefix + ".add_valid");
  wave.trace(acc, prefix + ".acc");
  wave.trace(product_counter, prefix + ".product_counter");
}

}  // namespace rtm
