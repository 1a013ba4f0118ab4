// What watches a simulation from inside (arbitration = ranked) or between slices of it (kernel):
// the stall watchdog and the budgets, and the progress line. machine.cpp looks through it every
// few thousand cycles.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include <systemc>

#include "machine/host.h"
#include "machine/pe.h"

namespace rtm {

/// The one-line progress display on stderr, redrawn at most twice a second.
class ProgressDisplay {
 public:
  explicit ProgressDisplay(uint64_t pixels) : pixels_(pixels) {}
  void draw(const std::vector<Pe*>& pes, const Host& host);
  bool drew() const { return drew_; }  ///< a progress line is on the terminal

 private:
  uint64_t pixels_;
  bool drew_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(),
                                        last_draw_ = start_;
};

class Watchdog {
 public:
  /// `pes` and `host` must outlive it; `progress`: null for no progress line. A budget of 0 is
  /// none.
  Watchdog(const Scene& s, const Grid& g, const MachineConfig& c, const std::vector<Pe*>& pes,
           const Host& host, uint64_t max_memory, uint64_t max_rays, ProgressDisplay* progress);

  /// How often it looks while things move.
  sc_core::sc_time base_step() const { return base_step_; }
  /// One look at the simulation, now: returns false, with the reason set (stalled, overran,
  /// over_budget, over_rays), when it must stop; else sets when to look next. It stops a
  /// simulation whose time passes the horizon, whose process holds more than the memory budget
  /// (read every 50 ms of wall time) or whose PEs traced more rays than the work budget, and one
  /// in which nothing has moved for longer than any unit takes over one item (a deadlock the
  /// clock would otherwise hide); and redraws the progress line. While nothing moves it looks less
  /// and less often, and across a long host phase not at all, so a long simulated time costs few
  /// looks.
  bool look(sc_core::sc_time& step);

  /// An upper bound on the PE cycles a ray can spend in the units without any of them finishing
  /// an item: each unit's longest item (units/unit_table.h) summed. The watchdog calls the loop
  /// stalled only after twice this with nothing done.
  static uint64_t longest_item_cycles(const Scene& s, const Grid& g, const MachineConfig& c);

  bool stalled = false;      ///< it stopped a simulation in which nothing moved
  bool overran = false;      ///< it stopped a simulation whose time passed the horizon
  uint64_t over_budget = 0;  ///< the resident size it stopped the simulation at; 0: it did not
  uint64_t over_rays = 0;  ///< the rays traced when it stopped it at the work budget; 0: it did not

 private:
  static constexpr double kStepCycles = 4096;
  static constexpr std::chrono::milliseconds kMeasureEvery{50};

  /// The units' items done by all PEs, and whether the rays traced passed the work budget.
  uint64_t work_done(bool& over);

  const std::vector<Pe*>& pes_;
  const Host& host_;
  uint64_t max_memory_, max_rays_;
  ProgressDisplay* progress_;
  sc_core::sc_time quiet_window_;  ///< this long with nothing done (and the host idle) is a stall
  sc_core::sc_time base_step_,
      longest_step_;  ///< how often it looks while things move, and at least
  sc_core::sc_time quiet_since_ = sc_core::SC_ZERO_TIME;
  uint64_t last_work_ = ~0ull, finished_work_ = 0, finished_rays_ = 0;
  std::vector<Pe*> active_;  ///< the PEs not yet finished
  std::chrono::steady_clock::time_point last_measured_ = std::chrono::steady_clock::now();
};

}  // namespace rtm
