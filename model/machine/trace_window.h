// When waveforms are recorded: a cycle range, for the PEs chosen.
#pragma once

#include <systemc>

namespace rtm {

struct TraceWindow {
  bool enabled = false;
  sc_core::sc_time from = sc_core::SC_ZERO_TIME;
  sc_core::sc_time to = sc_core::sc_max_time();

  bool now() const {
    if (!enabled) return false;
    const sc_core::sc_time t = sc_core::sc_time_stamp();
    return t >= from && t <= to;
  }
};

}  // namespace rtm
