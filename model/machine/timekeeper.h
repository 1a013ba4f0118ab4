// Same-cycle order (`arbitration = ranked`). SystemC does not order events due at the same
// time: which of two units finishing in the same cycle writes a shared FIFO first is up to the
// kernel's event queue, which anything else in it (the clock of clocked timing, for one) can
// reorder. In ranked order every timed wait of the model goes through one Timekeeper, which wakes
// the units due at a time in a fixed order (by rank: host first, then each PE's units), so the
// simulation, and its cycle counts, depend on nothing but the model.
#pragma once

#include <cstdint>
#include <queue>
#include <vector>

#include <systemc>

#include "units/wakeups.h"

namespace rtm {

class Timekeeper : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Timekeeper);
  explicit Timekeeper(sc_core::sc_module_name name);

  /// Suspends the calling process for `d`; among processes due at the same time, a lower rank
  /// resumes first. `wake` is the caller's own event (one outstanding wait per event).
  void wait(const sc_core::sc_time& d, int rank, sc_core::sc_event& wake);
  /// Notifies `wake` at absolute time `at` in rank order, without waiting (several may be posted
  /// for one event).
  void post(const sc_core::sc_time& at, int rank, sc_core::sc_event& wake);

 private:
  struct Due {
    sc_core::sc_time at;
    int rank;
    uint64_t seq;
    sc_core::sc_event* wake;
    bool operator>(const Due& o) const {
      if (at != o.at) return at > o.at;
      if (rank != o.rank) return rank > o.rank;
      return seq > o.seq;
    }
  };
  void run();

  std::priority_queue<Due, std::vector<Due>, std::greater<Due>> due_;
  sc_core::sc_event earlier_;  ///< a wait due before the one the keeper sleeps towards
  uint64_t seq_ = 0;
};

/// One process's waits: plain SystemC waits (`arbitration = kernel`) or through the keeper.
class Sleeper {
 public:
  Sleeper() = default;
  Sleeper(Timekeeper* keeper, int rank) : keeper_(keeper), rank_(rank) {}
  void operator()(const sc_core::sc_time& d) {
    if (keeper_ && d != sc_core::SC_ZERO_TIME)
      keeper_->wait(d, rank_, wake_);
    else
      sc_core::wait(d);
  }

  // A unit's wake-ups (units/wakeups.h): want() each time it asks for, then wait() for the earliest
  // or, if given, an input event (`either`: the input's events | event()).
  void want(uint64_t ticks) {
    if (!wakeups_.want(ticks, 0)) return;
    if (keeper_) keeper_->post(sc_core::sc_time::from_value(ticks), rank_, wake_);
  }
  void wait(const sc_core::sc_event_or_list* either) {
    if (!keeper_) {
      // The kernel keeps one pending notification per event: the earliest.
      wake_.cancel();
      const uint64_t next = wakeups_.next().first;
      if (next != Wakeups::kNever)
        wake_.notify(sc_core::sc_time::from_value(next - sc_core::sc_time_stamp().value()));
    }
    if (either)
      sc_core::wait(*either);
    else
      sc_core::wait(wake_);
    wakeups_.fired(sc_core::sc_time_stamp().value());
  }
  const sc_core::sc_event& event() const { return wake_; }

 private:
  Timekeeper* keeper_ = nullptr;
  int rank_ = 0;
  sc_core::sc_event wake_;
  Wakeups wakeups_;
};

}  // namespace rtm
