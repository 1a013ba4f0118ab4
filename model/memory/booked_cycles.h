// The cycles a memory port or bank is booked in (memory/local_memory_timing.h), as a bit per cycle
// from the oldest cycle still of interest: the reservation table books and tests single cycles
// millions of times a frame, which a tree of cycles paid for with an allocation each.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>

namespace rtm {

class BookedCycles {
 public:
  static constexpr uint64_t kNone = UINT64_MAX;

  bool booked(uint64_t cycle) const {
    if (cycle < base_) return false;
    const uint64_t w = (cycle - base_) / 64;
    return w < words_.size() && (words_[w] >> (cycle % 64) & 1);
  }
  void book(uint64_t cycle) {
    if (words_.empty()) base_ = cycle / 64 * 64;
    // A later request may take a slot before the earliest booked so far.
    for (; cycle < base_; base_ -= 64) words_.push_front(0);
    const uint64_t w = (cycle - base_) / 64;
    if (w >= words_.size()) words_.resize(w + 1, 0);
    words_[w] |= uint64_t(1) << (cycle % 64);
  }
  /// Books cycles from .. from + n - 1, a word at a time.
  void book(uint64_t from, uint64_t n) {
    if (n == 0) return;
    book(from);
    book(from + n - 1);  // the words now reach both ends
    for (uint64_t c = from, end = from + n; c < end;) {
      const uint64_t bit = c % 64, take = std::min<uint64_t>(64 - bit, end - c);
      words_[(c - base_) / 64] |= (take == 64 ? ~uint64_t(0) : (uint64_t(1) << take) - 1) << bit;
      c += take;
    }
  }
  /// The first booked cycle at or after `cycle`, or kNone.
  uint64_t next_booked(uint64_t cycle) const { return next(cycle, 0); }
  /// The first cycle at or after `cycle` that is not booked.
  uint64_t next_free(uint64_t cycle) const { return next(cycle, ~uint64_t(0)); }
  /// Nothing before `cycle` will be asked about again.
  void forget_before(uint64_t cycle) {
    while (!words_.empty() && base_ + 64 <= cycle) {
      words_.pop_front();
      base_ += 64;
    }
    if (words_.empty()) return;
    if (cycle > base_) words_.front() &= ~uint64_t(0) << (cycle - base_);
  }

 private:
  /// The first cycle >= `cycle` whose bit, flipped by `flip`, is set; outside the words every
  /// cycle is free.
  uint64_t next(uint64_t cycle, uint64_t flip) const {
    uint64_t c = cycle < base_ ? base_ : cycle;
    if (cycle < base_ && flip) return cycle;
    for (uint64_t w = (c - base_) / 64; w < words_.size(); ++w) {
      const uint64_t bits =
          (words_[w] ^ flip) & (w == (c - base_) / 64 ? ~uint64_t(0) << (c % 64) : ~uint64_t(0));
      if (bits) return base_ + 64 * w + uint64_t(__builtin_ctzll(bits));
    }
    return flip ? std::max(c, base_ + 64 * words_.size()) : kNone;
  }

  uint64_t base_ = 0;  ///< the cycle of words_[0]'s bit 0, a multiple of 64
  std::deque<uint64_t> words_;
};

}  // namespace rtm
