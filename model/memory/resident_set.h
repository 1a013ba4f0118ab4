// A fixed number of entries and which of them to replace: what the MAC's coefficient RAM
// (primitives) and the voxel cache (lines) keep.
#pragma once

#include <cstdint>
#include <list>
#include <unordered_map>

namespace rtm {

enum class Replacement {
  Lru,   ///< the least recently used goes
  Fifo,  ///< the one loaded longest ago goes, whatever its use since
};

template <class Key>
class ResidentSet {
 public:
  ResidentSet(uint64_t capacity, Replacement r) : capacity_(capacity), replacement_(r) {}

  /// True if `k` is resident (a hit); otherwise loads it (a miss), evicting another when full.
  /// Capacity 0 holds nothing: every access misses.
  bool access(const Key& k) {
    const auto it = where_.find(k);
    if (it != where_.end()) {
      if (replacement_ == Replacement::Lru) order_.splice(order_.begin(), order_, it->second);
      return true;
    }
    if (capacity_ == 0) return false;
    if (order_.size() == capacity_) {
      where_.erase(order_.back());
      order_.pop_back();
      ++evictions_;
    }
    order_.push_front(k);
    where_[k] = order_.begin();
    return false;
  }
  bool resident(const Key& k) const { return where_.count(k) != 0; }
  uint64_t evictions() const { return evictions_; }

 private:
  uint64_t capacity_;
  Replacement replacement_;
  std::list<Key> order_;  ///< the resident keys, the next to go last
  std::unordered_map<Key, typename std::list<Key>::iterator> where_;
  uint64_t evictions_ = 0;
};

}  // namespace rtm
