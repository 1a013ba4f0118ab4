// Which of several replicated units takes the next ray.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "config/config.h"

namespace rtm {

/// Replicated units waiting for a ray (the search units, the intersection units): each ray that
/// arrives goes to the waiting unit with the lowest number, so which unit takes a ray follows the
/// numbering, not the order in which a scheduler happens to wake units waiting on the same FIFO.
class LaneDispatcher {
 public:
  /// The most replicated units of a kind (search_units' bound).
  static constexpr int kMaxLanes = kMaxUnitsOfAKind;

  /// `lanes` waiting at first; the lanes numbered later must lie below kMaxLanes too (the
  /// configuration bounds search_units and intersection_units by it).
  explicit LaneDispatcher(int lanes = 0) {
    if (lanes < 0 || lanes > kMaxLanes)
      throw std::invalid_argument("LaneDispatcher: " + std::to_string(lanes) +
                                  " lanes; it holds 0 to " + std::to_string(kMaxLanes));
    for (int i = 0; i < lanes; ++i) idle(i);
  }
  void idle(int lane) {
    uint64_t& w = bits_[size_t(lane) / 64];
    const uint64_t bit = uint64_t(1) << (lane % 64);
    idle_ += !(w & bit);
    w |= bit;
  }
  void busy(int lane) {
    uint64_t& w = bits_[size_t(lane) / 64];
    const uint64_t bit = uint64_t(1) << (lane % 64);
    idle_ -= bool(w & bit);
    w &= ~bit;
  }
  bool any_idle() const { return idle_ > 0; }
  /// The lowest idle lane, now busy (any_idle() must hold).
  int take() {
    for (size_t w = 0;; ++w)
      if (bits_[w]) {
        const int bit = __builtin_ctzll(bits_[w]);
        bits_[w] &= bits_[w] - 1;
        --idle_;
        return int(w * 64) + bit;
      }
  }

 private:
  std::array<uint64_t, kMaxLanes / 64> bits_{};  ///< a bit per lane: waiting
  size_t idle_ = 0;                              ///< bits set
};

}  // namespace rtm
