// A cache of voxel data (the search units' voxel entries, the lanes' primitive lists) in front of
// a PE's local memory: optional, not in the paper (voxel_cache_bytes, 0: none). Lines of
// `line_bytes` hold aligned stretches of the address space; an access hits when every line it
// touches is there, and otherwise loads the lines that are not (each a read of line_bytes from the
// local memory, at the line's address), evicting what they replace:
//   direct_mapped  line n lives only in place n mod lines (the default: a tag compare, and voxel
//                  data is one array, so neighbouring voxels fall in different places);
//   lru            any place; the least recently used line goes.
#pragma once

#include <cstdint>
#include <vector>

#include "config/config.h"
#include "memory/resident_set.h"

namespace rtm {

class VoxelCache {
 public:
  enum class Placement { DirectMapped, Lru };

  /// voxel_cache_bytes, in lines of memory_bytes_per_cycle (a line fill is one beat), direct
  /// mapped.
  static VoxelCache from(const MachineConfig& c);
  /// floor(capacity / line) lines; none (every access misses, nothing is kept) when capacity <
  /// line. Throws std::invalid_argument for line_bytes 0.
  VoxelCache(uint64_t capacity_bytes, uint64_t line_bytes, Placement p = Placement::DirectMapped);

  /// A read of `bytes` (> 0) at `address`: how many lines it had to load (0: a hit).
  uint64_t access(uint64_t address, uint64_t bytes);

  uint64_t lines() const { return lines_; }
  uint64_t line_bytes() const { return line_; }
  uint64_t hits() const { return hits_; }
  uint64_t misses() const { return misses_; }
  uint64_t line_fills() const { return fills_; }
  /// hits / accesses; 1 before any access.
  double hit_rate() const {
    return hits_ + misses_ == 0 ? 1.0 : double(hits_) / double(hits_ + misses_);
  }

 private:
  bool line_access(uint64_t n);

  uint64_t line_, lines_;
  Placement placement_;
  std::vector<uint64_t> tags_;  ///< direct mapped: per place its line + 1, 0 when empty
  ResidentSet<uint64_t> lru_;
  uint64_t hits_ = 0, misses_ = 0, fills_ = 0;
};

}  // namespace rtm
