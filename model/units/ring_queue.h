// A first-in first-out queue on one growing ring: what std::deque does for the front buffer's
// waiting rays, without its block bookkeeping on every size(), push and pop.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace rtm {

template <class T>
class RingQueue {
 public:
  bool empty() const { return count_ == 0; }
  size_t size() const { return count_; }
  const T& front() const { return ring_[head_]; }
  void push_back(const T& v) {
    if (__builtin_expect(count_ == ring_.size(), 0)) grow();
    ring_[(head_ + count_++) & (ring_.size() - 1)] = v;
  }
  void pop_front() {
    head_ = (head_ + 1) & (ring_.size() - 1);
    --count_;
  }

 private:
  [[gnu::noinline]] void grow() {
    std::vector<T> bigger(ring_.empty() ? 16 : ring_.size() * 2);  // a power of two
    for (size_t i = 0; i < count_; ++i)
      bigger[i] = std::move(ring_[(head_ + i) & (ring_.size() - 1)]);
    ring_ = std::move(bigger);
    head_ = 0;
  }

  std::vector<T> ring_;  ///< count_ items from head_
  size_t head_ = 0, count_ = 0;
};

}  // namespace rtm
