// What both schedulers report of their FIFOs, written once: each scheduler only says where a
// FIFO's meter is (`meter_of(spec, lane)`: a FifoMeter&).
#pragma once

#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "units/fifo_meter.h"
#include "units/pe_state.h"

namespace rtm {

/// Calls f(spec, lane) for every FIFO the PE has, in the FIFO table's order, a per-lane FIFO
/// lane by lane.
template <class F>
void for_each_fifo(const PeState& pe, F&& f) {
  for (const FifoSpec& s : fifo_table()) {
    if (!pe.units.has(s)) continue;
    for (int lane = 0, n = fifo_count(s, pe.config); lane < n; ++lane) f(s, lane);
  }
}

using FifoStatsList = std::vector<std::pair<std::string, const FifoStats*>>;

/// Every FIFO's statistics, closed at `now`, named and ordered as for_each_fifo goes.
template <class MeterOf>
FifoStatsList fifo_stats(const PeState& pe, uint64_t now, double seconds_per_tick,
                         MeterOf&& meter_of) {
  FifoStatsList out;
  for_each_fifo(pe, [&](const FifoSpec& f, int lane) {
    out.emplace_back(f.name, &meter_of(f, lane).close(now, seconds_per_tick));
  });
  return out;
}

/// The front buffer's state and every FIFO's occupancy, for deadlock reports.
template <class Policy, class MeterOf>
std::string occupancy_report(const PeState& pe, const Policy& front, MeterOf&& meter_of) {
  std::ostringstream s;
  s << front.waiting() << " rays waiting in the front buffer, " << front.in_flight() << " past it;";
  for_each_fifo(pe, [&](const FifoSpec& f, int lane) {
    const FifoMeter& m = meter_of(f, lane);
    s << " " << f.name << " " << m.occupancy << "/" << m.stats.depth;
  });
  return s.str();
}

}  // namespace rtm
