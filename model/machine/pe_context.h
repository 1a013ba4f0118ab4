// A PE's units as SystemC sees them: the units' shared state (units/pe_state.h) plus the clock,
// the waveform window and the same-cycle order every module's waits go through.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <systemc>

#include "machine/timekeeper.h"
#include "machine/trace_window.h"
#include "machine/waveform.h"
#include "units/pe_state.h"

namespace rtm {

struct PeContext : PeState {
  sc_core::sc_time period;  ///< the PE clock period
  TraceWindow window;
  Timekeeper* keeper = nullptr;  ///< arbitration = ranked: every timed wait goes through it

  static uint64_t now() { return sc_core::sc_time_stamp().value(); }
  /// The time of a unit's put (record_put): only the event log and a streamed gather's pixel times
  /// read it, so without them the kernel is not asked.
  uint64_t put_time() const { return log || tracks_pixels() ? now() : 0; }
  /// A sleeper for one more process of this PE (`lane`: a root unit's).
  std::unique_ptr<Sleeper> sleeper(UnitKind kind, int lane = 0) const {
    return std::make_unique<Sleeper>(keeper, kRanksPerPe * (pe + 1) + int(kind) + lane);
  }
  static constexpr int kRanksPerPe = 128;  // more than UnitKind and 64 root lanes need
};

/// Busy flag and the id of the ray a unit works on, as traced variables. Outside the waveform
/// window they are left alone, so the VCD file records nothing there.
class UnitProbe {
 public:
  void begin(uint32_t ray_id) {
    if (!window_ || !window_->now()) return;
    busy_ = true;
    ray_id_ = ray_id;
  }
  void end() {
    if (window_ && window_->now()) busy_ = false;
  }
  /// Traces both under `scope` (the unit's hierarchical name): scope.busy, scope.ray_id.
  void trace(Waveform& wave, const std::string& scope, const TraceWindow* w) {
    window_ = w;
    wave.trace(busy_, scope + ".busy");
    wave.trace(ray_id_, scope + ".ray_id");
  }

 private:
  const TraceWindow* window_ = nullptr;
  bool busy_ = false;
  uint32_t ray_id_ = 0;
};

}  // namespace rtm
