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
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>

namespace rtm {

template <class Item>
class Pipeline {
 public:
  struct Slot {
    Item item;
    uint64_t due;
  };

  /// `cycle`: one cycle in the time unit the caller uses.
  explicit Pipeline(uint64_t cycle = 1) : cycle_(cycle) {}

  bool empty() const { return in_.empty(); }
  size_t size() const { return in_.size(); }
  const Slot& head() const { return in_.front(); }
  Slot& head() { return in_.front(); }
  uint64_t ready() const { return ready_; }
  /// Whether the head's result is due but not yet written at `now`.
  bool stalled(uint64_t now) const { return !in_.empty() && in_.front().due <= now; }
  bool can_accept(uint64_t now) const { return now >= ready_ && !stalled(now); }

  /// Accepts `item` at `now` (can_accept(now)); returns when its result is due.
  uint64_t accept(const Item& item, uint64_t now, uint64_t latency, uint64_t interval) {
    uint64_t due = now + latency;
    if (!in_.empty()) due = std::max(due, in_.back().due + cycle_);
    in_.push_back({item, due});
    ready_ = now + interval;
    return due;
  }

  /// The head's result was written at `now` (>= its due): removes and returns it.
  Item retire(uint64_t now) {
    const uint64_t due = in_.front().due, stall = now - due;
    Item item = in_.front().item;
    in_.pop_front();
    if (stall > 0) {
      for (Slot& s : in_) s.due += stall;
      ready_ = ready_ > due ? ready_ + stall : std::max(ready_, now);
    }
    return item;
  }

 private:
  uint64_t cycle_;
  std::deque<Slot> in_;
  uint64_t ready_ = 0;
};

}  // namespace rtm
