#include "memory/voxel_cache.h"

#include <stdexcept>

namespace rtm {
namespace {

uint64_t checked_line(uint64_t bytes) {
  if (bytes == 0) throw std::invalid_argument("voxel cache: a line of 0 bytes");
  return bytes;
}

}  // namespace

VoxelCache VoxelCache::from(const MachineConfig& c) {
  return VoxelCache(uint64_t(c.voxel_cache_bytes), uint64_t(c.memory_bytes_per_cycle));
}

VoxelCache::VoxelCache(uint64_t capacity_bytes, uint64_t line_bytes, Placement p)
    : line_(checked_line(line_bytes)),
      lines_(capacity_bytes / line_),
      placement_(p),
      tags_(p == Placement::DirectMapped ? lines_ : 0, 0),
      lru_(p == Placement::Lru ? lines_ : 0, Replacement::Lru) {}

uint64_t VoxelCache::access(uint64_t address, uint64_t bytes) {
  if (bytes == 0) throw std::invalid_argument("voxel cache: an access of 0 bytes");
  uint64_t loaded = 0;
  for (uint64_t n = address / line_; n <= (address + bytes - 1) / line_; ++n)
    loaded += !line_access(n);
  ++(loaded == 0 ? hits_ : misses_);
  fills_ += loaded;
  return loaded;
}

/// Whether line n is there; loads it if not.
bool VoxelCache::line_access(uint64_t n) {
  if (lines_ == 0) return false;
  if (placement_ == Placement::Lru) return lru_.access(n);
  uint64_t& tag = tags_[n % lines_];
  const bool hit = tag == n + 1;
  tag = n + 1;
  return hit;
}

}  // namespace rtm
