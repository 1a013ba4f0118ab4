// The MAC's coefficient RAM (paper §5.2: multiplier 2 reads "the RAM holding the primitive's
// quadric coefficients") as a store of primitives' coefficient records: which tests find their
// primitive's coefficients there (a hit) and which must load them from local memory first (a
// miss: the record, coef_record_bytes of memory/records.h, is read and replaces another's).
//
// Capacity 0: the RAM holds every primitive's coefficients, loaded before rendering with the rest
// of the scene (the literal reading of §5.2), so every access hits, the first included.
// Otherwise it holds `capacity` primitives and starts empty: the first access to each primitive
// misses (compulsory), and a miss with the RAM full evicts one:
//   lru   the least recently used (the default). A ray's next voxels and the next rays
//   (neighbouring
//         pixels, handed out one after another) list mostly the same primitives, so what was used
//         last is what is used next; for the handful of entries a RAM of this kind holds it takes a
//         few age bits each. Its known weakness: a cycle over capacity + 1 primitives misses every
//         time.
//   fifo  the one loaded longest ago (a rotating pointer: the cheapest hardware), to compare with.
#pragma once

#include <cstdint>

#include "memory/resident_set.h"

namespace rtm {

class CoefficientRam {
 public:
  explicit CoefficientRam(uint32_t capacity = 0, Replacement r = Replacement::Lru)
      : capacity_(capacity), held_(capacity, r) {}

  /// The MAC needs primitive `p`'s coefficients: true if they are in the RAM; false if they had to
  /// be loaded (a miss), evicting another primitive's when the RAM is full.
  bool access(uint32_t p) {
    const bool hit = capacity_ == 0 || held_.access(p);
    ++(hit ? hits_ : misses_);
    return hit;
  }
  bool resident(uint32_t p) const { return capacity_ == 0 || held_.resident(p); }

  uint32_t capacity() const { return capacity_; }
  uint64_t hits() const { return hits_; }
  uint64_t misses() const { return misses_; }
  uint64_t evictions() const { return held_.evictions(); }
  /// hits / accesses; 1 before any access.
  double hit_rate() const {
    return hits_ + misses_ == 0 ? 1.0 : double(hits_) / double(hits_ + misses_);
  }

 private:
  uint32_t capacity_;
  ResidentSet<uint32_t> held_;
  uint64_t hits_ = 0, misses_ = 0;
};

}  // namespace rtm
