// A FIFO's occupancy over time and the statistics it gives, whichever scheduler keeps the FIFO:
// the modules' MeteredFifo (machine/metered_fifo.h) and the PE engine's rings. Times are in ticks
// (SystemC time-resolution units); `seconds_per_tick` turns the time integral into seconds.
#pragma once

#include <cstdint>
#include <string>

namespace rtm {

struct FifoStats {
  std::string kind;  ///< e.g. "search", for grouping across PEs
  int depth = 0;
  int peak = 0;
  double occupancy_time = 0;  ///< ∫ occupancy dt, in seconds
  uint64_t writes = 0;        ///< records written (the cost's FIFO energy, cost/unit_cost.h)
};

struct FifoMeter {
  FifoStats stats;
  int occupancy = 0;
  uint64_t last_change = 0;
  uint64_t area = 0;  ///< ∫ occupancy dt, in ticks

  FifoMeter(const char* kind, int depth) {
    stats.kind = kind;
    stats.depth = depth;
  }
  void change(int delta, uint64_t now) {
    area += uint64_t(occupancy) * (now - last_change);
    last_change = now;
    occupancy += delta;
    if (delta > 0) stats.writes += uint64_t(delta);
    if (occupancy > stats.peak) stats.peak = occupancy;
  }
  /// The statistics, with the time integral closed at `now`.
  const FifoStats& close(uint64_t now, double seconds_per_tick) {
    change(0, now);
    stats.occupancy_time = double(area) * seconds_per_tick;
    return stats;
  }
};

}  // namespace rtm
