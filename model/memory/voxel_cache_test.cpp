// The voxel cache on hand-built addresses.
#include "memory/voxel_cache.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace rtm {
namespace {

TEST(VoxelCache, NeighbouringEntriesShareALine) {
  VoxelCache c(64, 16);  // 4 lines of 16 bytes
  EXPECT_EQ(c.lines(), 4u);
  EXPECT_EQ(c.access(0, 8), 1u);   // line 0 loaded
  EXPECT_EQ(c.access(8, 8), 0u);   // the same line
  EXPECT_EQ(c.access(12, 8), 1u);  // bytes 12..19: line 0 there, line 1 loaded
  EXPECT_EQ(c.access(16, 4), 0u);
  EXPECT_EQ(c.hits(), 2u);
  EXPECT_EQ(c.misses(), 2u);
  EXPECT_EQ(c.line_fills(), 2u);
  EXPECT_DOUBLE_EQ(c.hit_rate(), 0.5);
}

TEST(VoxelCache, DirectMappedLinesFourApartEvictEachOther) {
  VoxelCache c(64, 16);
  // Lines 0 and 4 share place 0; line 1 keeps place 1 throughout.
  EXPECT_EQ(c.access(0, 4), 1u);
  EXPECT_EQ(c.access(16, 4), 1u);
  EXPECT_EQ(c.access(64, 4), 1u);
  EXPECT_EQ(c.access(0, 4), 1u);
  EXPECT_EQ(c.access(16, 4), 0u);
  EXPECT_EQ(c.access(64, 4), 1u);
}

TEST(VoxelCache, LruKeepsTheLinesInUseWhereverTheyFall) {
  VoxelCache c(32, 16, VoxelCache::Placement::Lru);  // 2 lines, any place
  EXPECT_EQ(c.access(0, 4), 1u);                     // line 0
  EXPECT_EQ(c.access(64, 4), 1u);  // line 4: both held (direct mapped would evict line 0)
  EXPECT_EQ(c.access(0, 4), 0u);
  EXPECT_EQ(c.access(128, 4), 1u);  // line 8 evicts line 4, the least recently used
  EXPECT_EQ(c.access(0, 4), 0u);
  EXPECT_EQ(c.access(64, 4), 1u);
  VoxelCache d(32, 16);
  d.access(0, 4);
  d.access(64, 4);
  EXPECT_EQ(d.access(0, 4), 1u) << "direct mapped: lines 0 and 4 share place 0 of 2";
}

TEST(VoxelCache, NoLinesMeansEveryAccessMisses) {
  for (uint64_t capacity : {0u, 15u}) {
    VoxelCache c(capacity, 16);
    EXPECT_EQ(c.lines(), 0u);
    EXPECT_EQ(c.access(0, 8), 1u);
    EXPECT_EQ(c.access(0, 8), 1u);
    EXPECT_EQ(c.access(8, 16), 2u);
    EXPECT_EQ(c.hits(), 0u);
    EXPECT_EQ(c.line_fills(), 4u);
  }
  EXPECT_THROW(VoxelCache(64, 0), std::invalid_argument);
  VoxelCache c(64, 16);
  EXPECT_THROW(c.access(0, 0), std::invalid_argument);
}

TEST(VoxelCache, TheMachinesCacheHasLinesOfOneBeat) {
  MachineConfig c;
  EXPECT_EQ(VoxelCache::from(c).lines(), 0u) << "none by default";
  set_config(c, "voxel_cache_bytes", "1024");
  const VoxelCache v = VoxelCache::from(c);
  EXPECT_EQ(v.line_bytes(), uint64_t(c.memory_bytes_per_cycle));
  EXPECT_EQ(v.lines(), 1024u / uint64_t(c.memory_bytes_per_cycle));
}

}  // namespace
}  // namespace rtm
