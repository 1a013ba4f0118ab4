#include "frame/frame_stats.h"

#include <algorithm>
#include <cmath>

#include "frame/machine_result.h"

namespace rtm {

namespace {

/// Each unit's figure `of` (a UnitStats member), summed over the PEs and per replicated unit.
UnitShares sum(const MachineResult& m, const MachineConfig& c, uint64_t UnitStats::*of) {
  UnitShares u;
  for (const PeCounters& p : m.per_pe)
    for (const UnitSpec& s : unit_table())
      if (s.in_utilisation && unit_count(s.kind, c) > 0)
        u[s.kind] += double(p.total(s.kind).*of) / unit_count(s.kind, c);
  return u;
}

UnitShares divided(UnitShares u, double by) {
  for (double& x : u.of) x = by > 0 ? x / by : 0;
  return u;
}

/// `ticks` of simulated time in clock periods of `period` ticks (as sc_time divides them).
double in_cycles(uint64_t ticks, uint64_t period) { return double(ticks) / double(period); }

/// A PE's working window in cycles: its first primary ray handed out to its last ray ended, but
/// for its switches between frames.
double working_window(const PeCounters& p, uint64_t period) {
  return in_cycles(p.finish - p.start - p.frame_wait, period);
}

std::vector<SearchUnitShares> search_unit_shares(const PeCounters& p, uint64_t period) {
  const double w = working_window(p, period);
  std::vector<SearchUnitShares> shares;
  for (const UnitStats& u : p.units[size_t(UnitKind::Search)])
    shares.push_back(w > 0 ? SearchUnitShares{double(u.busy_cycles) / w, double(u.issue_cycles) / w}
                           : SearchUnitShares{});
  return shares;
}

/// Phases, unit figures over the PEs' working windows, credit stalls and load imbalance.
FrameProfile profile(const MachineResult& m, const MachineConfig& c) {
  const uint64_t period = m.clock_ticks;
  FrameProfile f;
  f.total = double(m.cycles);
  // Streamed rays overlap the host's work and the link's: what is not the host's work before the
  // transfer is done is waiting for the link.
  f.host_preprocess = in_cycles(m.host.work, period);
  f.transfer = in_cycles(m.host.transfer - m.host.work, period);
  f.pe = in_cycles(m.host.pes_done - m.host.transfer, period);
  f.gather = in_cycles(m.host.gathered - m.host.pes_done, period);
  f.gather_streamed = c.gather == MachineConfig::Gather::Streamed;
  f.pe_voxelisation = in_cycles(m.host.pe_voxelisation, period);
  const double frames = double(std::max<size_t>(1, m.frame_done.size()));
  if (frames > 1) {
    f.pipelined = true;
    f.total = m.frame_cycles();
    f.host_preprocess = in_cycles(m.host.work, period) / frames;
    uint64_t busiest = 0;
    for (const LinkUse& l : m.links) busiest = std::max(busiest, l.busy_ticks);
    f.transfer = in_cycles(busiest, period) / frames;
    f.gather = 0;
  }
  double window = 0, longest = 0, stall = 0, tile_wait = 0, memory_wait = 0, memory_access = 0,
         held = 0;
  for (size_t i = 0; i < m.per_pe.size(); ++i) {
    const PeCounters& p = m.per_pe[i];
    const double w = working_window(p, period);
    window += w;
    longest = std::max(longest, w);
    stall += in_cycles(p.credit_stall, period);
    tile_wait += in_cycles(p.tile_wait, period);
    held += double(p.all().held_cycles);
    if (i >= m.memory_use.size()) continue;
    memory_wait += double(m.memory_use[i].wait_cycles());
    memory_access += double(m.memory_use[i].access_cycles());
    // Of the frame, not the working window: the port also carries the host's writes before it.
    for (uint64_t busy : m.memory_use[i].port_busy_cycles)
      if (m.cycles > 0) f.memory_port = std::max(f.memory_port, double(busy) / double(m.cycles));
  }
  f.busy = divided(sum(m, c, &UnitStats::busy_cycles), window);
  f.issue = divided(sum(m, c, &UnitStats::issue_cycles), window);
  f.occupancy = divided(sum(m, c, &UnitStats::held_cycles), window);
  f.starved = divided(sum(m, c, &UnitStats::starved_cycles), window);
  if (window > 0) {
    f.credit_stall = stall / window;
    f.tile_wait = tile_wait / window;
    f.memory_wait = memory_wait / window;
    f.memory_access = held > 0 ? memory_access / held : 0;
    f.imbalance = longest / (window / double(m.per_pe.size()));
  }
  if (f.pipelined) f.pe = longest / frames;
  return f;
}

}  // namespace

FrameStats frame_stats(const MachineResult& m, const MachineConfig& c) {
  FrameStats s;
  s.utilisation = divided(sum(m, c, &UnitStats::busy_cycles), double(m.cycles) * c.pes);
  s.profile = profile(m, c);
  for (const PeCounters& p : m.per_pe)
    s.search_units.push_back(search_unit_shares(p, m.clock_ticks));
  s.bottleneck = bottleneck(s.profile);
  s.mac_bound_cycles = std::ceil(double(m.mac_products) / c.pes);
  s.cycles_over_mac_bound = s.mac_bound_cycles > 0 ? double(m.cycles) / s.mac_bound_cycles : 0.0;
  return s;
}

}  // namespace rtm
