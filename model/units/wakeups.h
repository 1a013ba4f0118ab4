// The times a unit has asked to be woken at, each with the order in which it was asked. A
// pipelined unit may wait for several things at once (its next result, its next acceptance, a
// retry on a full FIFO); both schedulers keep this list the same way, so a unit wakes at the same
// instants, ranked among the units of its kind by when it asked, under either of them.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace rtm {

class Wakeups {
 public:
  static constexpr uint64_t kNever = UINT64_MAX;

  /// Asks to be woken at t; false (and nothing changes) when a wake-up at t is already asked for.
  /// `order` is the caller's sequence number for it.
  bool want(uint64_t t, uint64_t order) {
    for (size_t i = 0; i < n_; ++i)
      if (at_[i].first == t) return false;
    if (n_ == at_.size()) at_.emplace_back();
    at_[n_++] = {t, order};
    return true;
  }
  /// The earliest wake-up: its time and order ({kNever, 0} when none).
  std::pair<uint64_t, uint64_t> next() const {
    std::pair<uint64_t, uint64_t> best{kNever, 0};
    for (size_t i = 0; i < n_; ++i)
      if (at_[i].first < best.first) best = at_[i];
    return best;
  }
  /// The wake-ups at `now` have happened.
  void fired(uint64_t now) { (void)fire(now); }
  /// fired(now), then next(), in one pass.
  std::pair<uint64_t, uint64_t> fire(uint64_t now) {
    std::pair<uint64_t, uint64_t> best{kNever, 0};
    for (size_t i = 0; i < n_;) {
      if (at_[i].first <= now) {
        at_[i] = at_[--n_];
        continue;
      }
      if (at_[i].first < best.first) best = at_[i];
      ++i;
    }
    return best;
  }
  bool empty() const { return n_ == 0; }

 private:
  std::vector<std::pair<uint64_t, uint64_t>> at_;  ///< the first n_ are asked for: a few at most
  size_t n_ = 0;
};

}  // namespace rtm
