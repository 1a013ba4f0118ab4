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

namespace rtm {

class Timekeeper : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Timekeeper);
  explicit Timekeeper(sc_core::sc_module_name name);

  /// Suspends the calling process for `d`; among processes due at the same time, a lower rank
  /// resumes first. `wake` is the caller's own event (one outstanding wait per event).
  void wait(const sc_core::sc_time& d, int rank, sc_core::sc_event& wake);

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

 private:
  Timekeeper* keeper_ = nullptr;
  int rank_ = 0;
  sc_core::sc_event wake_;
};

}  // namespace rtm
