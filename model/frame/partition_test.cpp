#include "frame/partition.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace rtm {
namespace {

MachineConfig with(Partition p, int pes, int tile = 16) {
  MachineConfig c;
  c.partition = p;
  c.pes = pes;
  c.tile = tile;
  return c;
}

class EveryScheme : public ::testing::TestWithParam<Partition> {};

TEST_P(EveryScheme, EveryPixelExactlyOnceInScanOrder) {
  for (int pes : {1, 2, 3, 7, 64}) {
    const auto parts = partition_screen(37, 23, with(GetParam(), pes, 5));
    ASSERT_EQ(parts.size(), size_t(pes));
    std::vector<int> seen(37 * 23, 0);
    for (const auto& part : parts) {
      EXPECT_TRUE(std::is_sorted(part.begin(), part.end()));
      for (uint32_t px : part) ++seen[px];
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }))
        << pes << " PEs";
  }
}

TEST_P(EveryScheme, CountsThePesLeftWithoutPixels) {
  for (int pes : {1, 2, 3, 7, 64, 1000}) {
    const MachineConfig c = with(GetParam(), pes, 5);
    const auto parts = partition_screen(37, 23, c);
    EXPECT_EQ(pes_without_pixels(37, 23, c),
              std::count_if(parts.begin(), parts.end(), [](const auto& p) { return p.empty(); }))
        << pes << " PEs";
  }
}

INSTANTIATE_TEST_SUITE_P(Partition, EveryScheme,
                         ::testing::Values(Partition::Scanlines, Partition::Blocks,
                                           Partition::Strips, Partition::Pixels));

TEST(Partition, BlocksOfATenPixelFrameLeaveTwoOfThreePesIdle) {
  EXPECT_EQ(pes_without_pixels(10, 10, with(Partition::Blocks, 3)), 2);  // one 16x16 tile
  EXPECT_EQ(pes_without_pixels(10, 10, with(Partition::Scanlines, 3)), 0);
}

TEST(Partition, ScanlinesInterleaveRows) {
  const auto parts = partition_screen(4, 5, with(Partition::Scanlines, 2));
  EXPECT_EQ(parts[0], (std::vector<uint32_t>{0, 1, 2, 3, 8, 9, 10, 11, 16, 17, 18, 19}));
}

TEST(Partition, PixelsGiveEveryPeEveryNthPixelOfEveryRowSheared) {
  const int w = 64, h = 16, n = 8;
  const auto parts = partition_screen(w, h, with(Partition::Pixels, n));
  for (const auto& part : parts) {
    ASSERT_EQ(part.size(), size_t(w / n * h));
    std::set<uint32_t> rows, columns;
    for (uint32_t px : part) {
      rows.insert(px / w);
      columns.insert(px % w);
    }
    EXPECT_EQ(rows.size(), size_t(h));         // every row
    EXPECT_GT(columns.size(), size_t(w / n));  // and not the same columns in every row
  }
  // Neighbouring pixels of a row go to different PEs.
  EXPECT_NE(std::find(parts[0].begin(), parts[0].end(), 0u), parts[0].end());
  EXPECT_EQ(std::find(parts[0].begin(), parts[0].end(), 1u), parts[0].end());
}

}  // namespace
}  // namespace rtm
