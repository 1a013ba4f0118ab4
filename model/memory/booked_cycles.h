// The cycles a memory port or bank is booked in (memory/local_memory_timing.h), as a bit per cycle
// from the oldest cycle still of interest: the reservation table books and tests single cycles
// millions of times a frame, which a tree of cycles paid for with an allocation each.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rtm {

class BookedCycles {
 public:
  static constexpr uint64_t kNone = UINT64_MAX;

  bool booked(uint64_t cycle) const {
    if (cycle < base_) return false;
    const uint64_t w = (cycle - base_) / 64;
    return w < size_ && (word(w) >> (cycle % 64) & 1);
  }
  void book(uint64_t cycle) {
    if (size_ == 0) base_ = cycle / 64 * 64;
    // A later request may take a slot before the earliest booked so far.
    for (; cycle < base_; base_ -= 64) push_front();
    const uint64_t w = (cycle - base_) / 64;
    while (w >= size_) push_back();
    word(w) |= uint64_t(1) << (cycle % 64);
  }
  /// Books cycles from .. from + n - 1, a word at a time.
  void book(uint64_t from, uint64_t n) {
    if (n == 0) return;
    book(from);
    book(from + n - 1);  // the words now reach both ends
    for (uint64_t c = from, end = from + n; c < end;) {
      const uint64_t bit = c % 64, take = std::min<uint64_t>(64 - bit, end - c);
      word((c - base_) / 64) |= (take == 64 ? ~uint64_t(0) : (uint64_t(1) << take) - 1) << bit;
      c += take;
    }
  }
  /// The first booked cycle at or after `cycle`, or kNone.
  uint64_t next_booked(uint64_t cycle) const { return next(cycle, 0); }
  /// The first cycle at or after `cycle` that is not booked.
  uint64_t next_free(uint64_t cycle) const { return next(cycle, ~uint64_t(0)); }
  /// Nothing before `cycle` will be asked about again.
  void forget_before(uint64_t cycle) {
    while (size_ != 0 && base_ + 64 <= cycle) {
      head_ = (head_ + 1) & mask();
      --size_;
      base_ += 64;
    }
    if (size_ == 0) return;
    if (cycle > base_) word(0) &= ~uint64_t(0) << (cycle - base_);
  }

 private:
  /// The first cycle >= `cycle` whose bit, flipped by `flip`, is set; outside the words every
  /// cycle is free.
  uint64_t next(uint64_t cycle, uint64_t flip) const {
    uint64_t c = cycle < base_ ? base_ : cycle;
    if (cycle < base_ && flip) return cycle;
    for (uint64_t w = (c - base_) / 64; w < size_; ++w) {
      const uint64_t bits =
          (word(w) ^ flip) & (w == (c - base_) / 64 ? ~uint64_t(0) << (c % 64) : ~uint64_t(0));
      if (bits) return base_ + 64 * w + uint64_t(__builtin_ctzll(bits));
    }
    return flip ? std::max(c, base_ + 64 * size_) : kNone;
  }

  // The words from base_ on, size_ of them from ring_[head_] round a ring whose size is a power
  // of two: booking and forgetting move its ends, which a deque paid for in its block map.
  uint64_t mask() const { return ring_.size() - 1; }
  uint64_t& word(uint64_t w) { return ring_[(head_ + w) & mask()]; }
  uint64_t word(uint64_t w) const { return ring_[(head_ + w) & mask()]; }
  void grow() {
    std::vector<uint64_t> bigger(ring_.empty() ? 4 : ring_.size() * 2, 0);
    for (uint64_t w = 0; w < size_; ++w) bigger[w] = word(w);
    ring_ = std::move(bigger);
    head_ = 0;
  }
  void push_back() {
    if (size_ == ring_.size()) grow();
    word(size_++) = 0;
  }
  void push_front() {
    if (size_ == ring_.size()) grow();
    head_ = (head_ - 1) & mask();
    ++size_;
    word(0) = 0;
  }

  uint64_t base_ = 0;  ///< the cycle of word 0's bit 0, a multiple of 64
  std::vector<uint64_t> ring_;
  uint64_t head_ = 0, size_ = 0;
};

}  // namespace rtm
