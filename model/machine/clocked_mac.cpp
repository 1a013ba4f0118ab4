#include "machine/clocked_mac.h"

namespace rtm {

using sc_core::sc_time;

ClockedMac::ClockedMac(sc_core::sc_module_name name, const MacTiming& timing, Precision precision,
                       sc_time period)
    : sc_module(name), mac_(timing, precision), period_(period) {
  SC_THREAD(clocked);
}

void ClockedMac::start(MacJob job) {
  mac_.start(std::move(job));
  posted_.notify();
}

ClockedMac::Done ClockedMac::run(MacJob job) {
  start(std::move(job));
  Done d;
  while (!finish(d)) sc_core::wait(finished_);
  return d;
}

void ClockedMac::clocked() {
  ClockLevelMac::Registers regs;
  for (;;) {
    if (mac_.idle()) sc_core::wait(posted_);
    // The clock's rising edges fall mid-cycle (see Machine): a job posted at a cycle boundary
    // runs its cycle 0 on the next one.
    sc_core::wait(clk.posedge_event());
    if (stalled_) continue;
    const bool tracing = window_ && window_->now();
    // A job's sums are in the accumulator at its last edge; the stage takes them at the next
    // cycle boundary.
    if (mac_.edge(tracing ? &regs : nullptr)) finished_.notify(period_ / 2);
    if (tracing) trace_edge(regs);
  }
}

void ClockedMac::trace_edge(const ClockLevelMac::Registers& r) {
  m1_valid.write(r.m1_valid);
  if (r.m1_valid) m1_a.write(r.m1_a), m1_b.write(r.m1_b);
  if (r.m2_valid) m1_out.write(r.m1_out), m2_coef.write(r.m2_coef);
  m2_valid.write(r.m2_valid);
  if (r.add_valid) m2_out.write(r.m2_out);
  add_valid.write(r.add_valid);
  if (r.accumulated) {
    acc.write(r.acc);
    abg_select.write(r.abg_select);
    adder_ray_id.write(r.ray_id);
    prim.write(r.prim);
    product_counter.write(r.product_counter);
  }
  if (r.sums_valid) alpha.write(r.alpha), beta.write(r.beta), gamma.write(r.gamma);
  sums_valid.write(r.sums_valid);
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
