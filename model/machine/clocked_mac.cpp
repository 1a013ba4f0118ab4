#include "machine/clocked_mac.h"

#include <algorithm>
#include <deque>

namespace rtm {

using sc_core::sc_time;

ClockedMac::ClockedMac(sc_core::sc_module_name name, const MacTiming& timing, Precision precision,
                       sc_time period)
    : sc_module(name),
      timing_(timing),
      precision_(precision),
      period_(period),
      mul1_(size_t(timing.mul_latency)),
      mul2_(size_t(timing.mul_latency)),
      adder_(size_t(timing.add_latency)) {
  SC_THREAD(clocked);
}

void ClockedMac::start(MacJob job) {
  Posted p;
  std::vector<int> counts;
  for (size_t i = 0; i < job.rams.size(); ++i)
    counts.push_back(job.ops.empty() ? kMacProducts : int(job.ops[i].size()));
  p.plan = timing_.job(counts, job.loads);
  p.done.sums.assign(job.rams.size(), {0, 0, 0});
  p.job = std::move(job);
  p.start = tick_;  // the next edge runs cycle tick_
  jobs_.push_back(std::move(p));
  posted_.notify();
}

bool ClockedMac::finish(Done& done) {
  if (jobs_.empty() || !jobs_.front().finished) return false;
  done = std::move(jobs_.front().done);
  jobs_.pop_front();
  ++first_serial_;
  return true;
}

ClockedMac::Done ClockedMac::run(MacJob job) {
  start(std::move(job));
  Done d;
  while (!finish(d)) sc_core::wait(finished_);
  return d;
}

bool ClockedMac::idle() const {
  if (!jobs_.empty() && !jobs_.back().finished) return false;
  const auto empty = [](const std::deque<Stage>& r) {
    return std::none_of(r.begin(), r.end(), [](const Stage& s) { return s.valid; });
  };
  return empty(mul1_) && empty(mul2_) && empty(adder_);
}

void ClockedMac::clocked() {
  for (;;) {
    if (idle()) sc_core::wait(posted_);
    // The clock's rising edges fall mid-cycle (see Machine): a job posted at a cycle boundary
    // runs its cycle 0 on the next one.
    sc_core::wait(clk.posedge_event());
    if (!stalled_) edge();
  }
}

// One edge, stage by stage from the pipeline's end to its start (each stage takes what the one
// before it held at the last edge), then the registers' signals.
void ClockedMac::edge() {
  const bool tracing = window_ && window_->now();
  const bool handed = accumulate(tracing);
  const Stage m2 = multiply_by_coefficient();
  const Stage m1 = multiply_latches();
  const Stage in = issue();
  mul1_.push_front(in);
  ++tick_;
  if (tracing) trace_edge(in, m1, m2, handed);
}

bool ClockedMac::accumulate(bool tracing) {
  // Adder: accumulate the product leaving it into α, β or γ.
  const Stage out = adder_.back();
  adder_.pop_back();
  if (!out.valid) return false;
  Posted& j = job(out.job);
  const MacOp& op = kMacSchedule[size_t(out.k)];
  sum_[op.sum] = round_to(precision_, sum_[op.sum] + out.value);
  ++accumulated_;
  if (tracing) {
    acc.write(sum_[op.sum]);
    abg_select.write(uint32_t(op.sum));
    adder_ray_id.write(j.job.ray_id);
    prim.write(uint32_t(out.prim));
    product_counter.write(accumulated_);
  }
  if (!out.last) return false;
  j.done.sums[size_t(out.prim)] = {sum_[0], sum_[1], sum_[2]};
  if (tracing) alpha.write(sum_[0]), beta.write(sum_[1]), gamma.write(sum_[2]);
  sum_[0] = sum_[1] = sum_[2] = 0;
  if (out.prim + 1 == int(j.done.sums.size())) {
    j.done.cycles = tick_ - j.start + 1;
    j.finished = true;
    accumulated_ = 0;
    // The sums are in the accumulator at this edge; the stage takes them at the next cycle
    // boundary.
    finished_.notify(period_ / 2);
  }
  return true;
}

ClockedMac::Stage ClockedMac::multiply_by_coefficient() {
  // Multiplier 2: multiplier 1's product times the coefficient RAM word.
  Stage m2 = mul2_.back();
  mul2_.pop_back();
  if (m2.valid)
    m2.value = round_to(
        precision_, m2.value * job(m2.job).job.rams[size_t(m2.prim)][kMacSchedule[size_t(m2.k)].w]);
  adder_.push_front(m2);
  return m2;
}

ClockedMac::Stage ClockedMac::multiply_latches() {
  // Multiplier 1: two latch operands.
  Stage m1 = mul1_.back();
  mul1_.pop_back();
  if (m1.valid) {
    const MacOp& op = kMacSchedule[size_t(m1.k)];
    const Latches<double>& l = job(m1.job).job.latches[size_t(m1.prim)];
    m1.value = round_to(precision_, l[op.x] * l[op.y]);
  }
  mul2_.push_front(m1);
  return m1;
}

ClockedMac::Stage ClockedMac::issue() {
  // The next product when the schedule says so: the oldest job with products left.
  Stage in;
  for (size_t i = 0; i < jobs_.size(); ++i) {
    Posted& j = jobs_[i];
    const int prims = int(j.plan.counts.size());
    if (j.prim == prims) continue;
    if (tick_ == j.start + j.plan.issue(j.prim, j.j)) {
      in.valid = true;
      in.job = first_serial_ + i;
      in.prim = j.prim;
      in.k = j.job.ops.empty() ? j.j : j.job.ops[size_t(j.prim)][size_t(j.j)];
      in.last = j.j + 1 == j.plan.counts[size_t(j.prim)];
      if (in.last) {
        ++j.prim;
        j.j = 0;
      } else {
        ++j.j;
      }
    }
    break;
  }
  return in;
}

void ClockedMac::trace_edge(const Stage& in, const Stage& m1, const Stage& m2, bool handed) {
  m1_valid.write(in.valid);
  if (in.valid) {
    const MacOp& op = kMacSchedule[size_t(in.k)];
    const Latches<double>& l = job(in.job).job.latches[size_t(in.prim)];
    m1_a.write(l[op.x]);
    m1_b.write(l[op.y]);
  }
  if (m1.valid)
    m1_out.write(m1.value),
        m2_coef.write(job(m1.job).job.rams[size_t(m1.prim)][kMacSchedule[size_t(m1.k)].w]);
  m2_valid.write(m1.valid);
  if (m2.valid) m2_out.write(m2.value);
  add_valid.write(m2.valid);
  sums_valid.write(handed);
}

void ClockedMac::trace(Waveform& wave, const std::string& prefix, const TraceWindow* window) {
  window_ = window;
  wave.trace(adder_ray_id, prefix + ".adder_ray_id");
  wave.trace(m1_valid, prefix + ".m1_valid");
  wave.trace(m1_a, prefix + ".m1_a");
  wave.trace(m1_b, prefix + ".m1_b");
  wave.trace(m1_out, prefix + ".m1_out");
  wave.trace(m2_valid, prefix + ".m2_valid");
  wave.trace(m2_coef, prefix + ".m2_coef");
  wave.trace(m2_out, prefix + ".m2_out");
  wave.trace(add_valid, prefix + ".add_valid");
  wave.trace(acc, prefix + ".acc");
  wave.trace(abg_select, prefix + ".abg_select");
  wave.trace(product_counter, prefix + ".product_counter");
  wave.trace(prim, prefix + ".prim");
  wave.trace(sums_valid, prefix + ".sums_valid");
  wave.trace(alpha, prefix + ".alpha");
  wave.trace(beta, prefix + ".beta");
  wave.trace(gamma, prefix + ".gamma");
}

}  // namespace rtm
