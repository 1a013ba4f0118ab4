#include "machine/frame_stats.h"

#include <algorithm>
#include <cmath>

#include "machine/machine.h"

namespace rtm {

namespace {

/// Busy fraction of each unit over the frame.
FrameUtilisation utilisation(const MachineResult& m, const MachineConfig& c) {
  FrameUtilisation u;
  const double cycles = double(m.cycles) * c.pes;
  if (cycles <= 0) return u;
  for (const PeCounters& p : m.per_pe) {
    u.front_buffer += double(p.front.busy_cycles);
    u.search += double(p.search.busy_cycles) / c.search_units;
    u.mac += double(p.mac.busy_cycles) / c.intersection_units;
    u.root += double(p.root.busy_cycles) / c.intersection_units;
    u.shading += double(p.shade.busy_cycles);
  }
  for (double* x : {&u.front_buffer, &u.search, &u.mac, &u.root, &u.shading}) *x /= cycles;
  return u;
}

/// Phases, unit utilisation over the PEs' working windows, credit stalls and load imbalance.
FrameProfile profile(const MachineResult& m, const MachineConfig& c) {
  const sc_core::sc_time period(c.clock_ns, sc_core::SC_NS);
  FrameProfile f;
  f.total = double(m.cycles);
  f.host_preprocess = m.host.rays / period;
  f.transfer = (m.host.transfer - m.host.rays) / period;
  f.pe = (m.host.pes_done - m.host.transfer) / period;
  f.gather = (m.host.gathered - m.host.pes_done) / period;
  double window = 0, longest = 0, stall = 0;
  for (const PeCounters& p : m.per_pe) {
    const double w = sc_core::sc_time::from_value(p.finish - p.start) / period;
    window += w;
    longest = std::max(longest, w);
    stall += sc_core::sc_time::from_value(p.credit_stall) / period;
    f.search += double(p.search.busy_cycles) / c.search_units;
    f.mac += double(p.mac.busy_cycles) / c.intersection_units;
    f.root += double(p.root.busy_cycles) / c.intersection_units;
    f.shading += double(p.shade.busy_cycles);
    f.front_buffer += double(p.front.busy_cycles);
  }
  if (window > 0) {
    for (double* u : {&f.search, &f.mac, &f.root, &f.shading, &f.front_buffer}) *u /= window;
    f.credit_stall = stall / window;
    f.imbalance = longest / (window / double(m.per_pe.size()));
  }
  return f;
}

}  // namespace

FrameStats frame_stats(const MachineResult& m, const MachineConfig& c) {
  FrameStats s;
  s.utilisation = utilisation(m, c);
  s.profile = profile(m, c);
  s.bottleneck = bottleneck(s.profile);
  s.mac_bound_cycles = std::ceil(double(m.mac_products) / c.pes);
  s.cycles_over_mac_bound = s.mac_bound_cycles > 0 ? double(m.cycles) / s.mac_bound_cycles : 0.0;
  return s;
}

}  // namespace rtm
