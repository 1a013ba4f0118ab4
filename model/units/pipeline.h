// A pipelined unit in time (paper §2 ③: every stage is pipelined inside). Both schedulers keep one
// per unit and follow its rules, so they agree on every cycle.
//
// An item accepted at time a, with latency L and interval I (Work::cycles, Work::interval):
//  - its result is due at a + L, but no earlier than one cycle after the result ahead of it still
//    inside: results leave in order, one a cycle;
//  - the next item may be accepted from a + I on;
//  - a result that cannot be written (its FIFO is full) stalls the whole pipeline: nothing is
//    accepted, and every item inside and the next acceptance move by as many cycles as the result
//    waited. A unit whose acceptance was already possible when the stall began may accept again
//    once the result is written.
// With I = L a unit holds one item at a time: unpipelined. docs/machine.md, "Pipelined units".
//
// It also keeps the unit's statistics (UnitStats), in whole cycles: busy while it holds any item,
// its entry occupied for each item's interval, item-cycles held (occupancy once divided by
// time), and starved while it could take an item but its input was empty (from its first item on).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "units/pe_memory.h"

namespace rtm {

/// One unit's statistics, or the sum over replicated units.
struct UnitStats {
  uint64_t items = 0;
  uint64_t busy_cycles = 0;     ///< holding at least one item
  uint64_t issue_cycles = 0;    ///< the intervals of the items taken: the entry's utilisation
  uint64_t held_cycles = 0;     ///< the sum over items of the cycles each spent inside
  uint64_t starved_cycles = 0;  ///< able to take an item, none there

  UnitStats& operator+=(const UnitStats& o) {
    items += o.items;
    busy_cycles += o.busy_cycles;
    issue_cycles += o.issue_cycles;
    held_cycles += o.held_cycles;
    starved_cycles += o.starved_cycles;
    return *this;
  }
};

template <class Item>
class Pipeline {
 public:
  struct Slot {
    Item item;
    uint64_t due;
    uint64_t accepted;
    MemoryWait wait;  ///< its local-memory requests whose data may come late (units/pe_memory.h)
  };

  /// `cycle`: one cycle in the time unit the caller uses; `stats`: where to count (may be null).
  explicit Pipeline(uint64_t cycle = 1, UnitStats* stats = nullptr)
      : cycle_(cycle), stats_(stats ? stats : &own_) {}

  bool empty() const { return count_ == 0; }
  size_t size() const { return count_; }
  const Slot& head() const { return ring_[head_]; }
  Slot& head() { return ring_[head_]; }
  uint64_t ready() const { return ready_; }
  /// Whether the head's result is due but not yet written at `now`.
  bool stalled(uint64_t now) const { return count_ > 0 && head().due <= now; }
  bool can_accept(uint64_t now) const { return now >= ready_ && !stalled(now); }

  /// Accepts `item` at `now` (can_accept(now)), its latency and interval in cycles; returns when
  /// its result is due.
  [[gnu::always_inline]] uint64_t accept(const Item& item, uint64_t now, uint64_t latency,
                                         uint64_t interval, MemoryWait&& wait = {}) {
    uint64_t due = now + latency * cycle_;
    if (count_ == 0)
      busy_since_ = now;
    else
      due = std::max(due, at(count_ - 1).due + cycle_);
    if (count_ == mask_ + 1) grow();
    Slot& s = at(count_++);
    s.item = item;
    s.due = due;
    s.accepted = now;
    if (!wait.empty() || !s.wait.empty())
      s.wait = std::move(wait);  // most items ask nothing of memory
    ready_ = now + interval * cycle_;
    ++stats_->items;
    stats_->issue_cycles += interval;
    fed_ = true;
    return due;
  }

  /// The unit waits for input from `now` (it could take an item): starved until it wakes.
  void starve(uint64_t now) {
    if (fed_ && !starving_) starving_ = true, starved_since_ = now;
  }
  /// The unit woke at `now`: a wait for input, if any, is over.
  void woke(uint64_t now) {
    if (!starving_) return;
    starving_ = false;
    stats_->starved_cycles += (now - starved_since_) / cycle_;
  }

  /// The head's result was written at `now` (>= its due): removes and returns it.
  Item retire(uint64_t now) {
    const uint64_t due = head().due, stall = now - due;
    Item item = std::move(head().item);
    stats_->held_cycles += (now - head().accepted) / cycle_;
    head_ = (head_ + 1) & mask_;
    if (--count_ == 0) stats_->busy_cycles += (now - busy_since_) / cycle_;
    if (stall > 0) {
      for (size_t i = 0; i < count_; ++i) at(i).due += stall;
      ready_ = ready_ > due ? ready_ + stall : std::max(ready_, now);
    }
    return item;
  }

 private:
  /// The i-th item from the head (the ring's size is a power of two).
  Slot& at(size_t i) { return ring_[(head_ + i) & mask_]; }
  void grow() {
    std::vector<Slot> bigger(ring_.empty() ? 4 : ring_.size() * 2);
    for (size_t i = 0; i < count_; ++i) bigger[i] = std::move(at(i));
    ring_ = std::move(bigger);
    mask_ = ring_.size() - 1;
    head_ = 0;
  }

  uint64_t cycle_;
  UnitStats own_;
  UnitStats* stats_;
  std::vector<Slot> ring_;    ///< the items inside, count_ of them from head_
  size_t mask_ = size_t(-1);  ///< ring_.size() - 1, kept: the size of a Slot is no power of two
  size_t head_ = 0, count_ = 0;
  uint64_t ready_ = 0;
  uint64_t busy_since_ = 0, starved_since_ = 0;
  bool fed_ = false, starving_ = false;
};

}  // namespace rtm
