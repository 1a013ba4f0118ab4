// When waveforms are recorded: a cycle range, for the PEs chosen; absolute, or counted from the
// moment one PE hands out its first primary ray (the host's pre-processing comes first and can
// take most of a small frame, so an absolute window easily records nothing).
#pragma once

#include <memory>
#include <utility>

#include <systemc>

namespace rtm {

/// The start a relative window counts from: when PE `pe` hands out its first primary ray.
struct WindowAnchor {
  int pe = 0;
  sc_core::sc_time at = sc_core::sc_max_time();  ///< not yet
};

struct TraceWindow {
  bool enabled = false;
  sc_core::sc_time from = sc_core::SC_ZERO_TIME;  ///< after the anchor's time when there is one
  sc_core::sc_time to = sc_core::sc_max_time();
  std::shared_ptr<WindowAnchor>
      anchor;  ///< shared by every PE's window; null: from and to are absolute

  bool now() const {
    if (!enabled) return false;
    const sc_core::sc_time t = sc_core::sc_time_stamp();
    const sc_core::sc_time base = anchor ? anchor->at : sc_core::SC_ZERO_TIME;
    if (t < base || base == sc_core::sc_max_time()) return false;
    return t - base >= from && t - base <= to;
  }
  /// PE `pe` handed out its first primary ray now.
  void pe_started(int pe) const {
    if (anchor && anchor->pe == pe) anchor->at = sc_core::sc_time_stamp();
  }
  /// Whether the window has a place in time yet (a relative one once its PE has started).
  bool placed() const { return !anchor || anchor->at != sc_core::sc_max_time(); }
  /// Where the window lies in simulated time, its end clipped to `end`; placed() windows only.
  std::pair<sc_core::sc_time, sc_core::sc_time> span(sc_core::sc_time end) const {
    const sc_core::sc_time base = anchor ? anchor->at : sc_core::SC_ZERO_TIME;
    auto at = [&](sc_core::sc_time offset) {
      return offset >= end - base ? end : base + offset;
    };  // no overflow
    return {at(from), at(to)};
  }
};

}  // namespace rtm
