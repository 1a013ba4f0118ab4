#include "frame/tiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <queue>
#include <tuple>

namespace rtm {
namespace {

TEST(Tiles, CoverTheScreenInScanOrderTheLastOnesCut) {
  const auto tiles = screen_tiles(37, 23, 16);  // 3 x 2 tiles, the right column 5 wide
  ASSERT_EQ(tiles.size(), 6u);
  EXPECT_EQ(std::make_tuple(tiles[2].x, tiles[2].y, tiles[2].width, tiles[2].height),
            std::make_tuple(32u, 0u, 5u, 16u));
  EXPECT_EQ(std::make_tuple(tiles[5].x, tiles[5].y, tiles[5].width, tiles[5].height),
            std::make_tuple(32u, 16u, 5u, 7u));
  EXPECT_EQ(tile_pixels(tiles[5], 37).front(), 16u * 37u + 32u);
  EXPECT_EQ(tile_pixels(tiles[5], 37).size(), 35u);
}

TEST(Tiles, ATileLargerThanTheScreenIsTheScreen) {
  const auto tiles = screen_tiles(10, 10, 16);
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_EQ(tiles[0].pixels(), 100u);
}

TEST(Tiles, BadSizesAreNamed) {
  EXPECT_THROW(screen_tiles(10, 10, 0), std::invalid_argument);
  EXPECT_THROW(screen_tiles(0, 10, 4), std::invalid_argument);
}

TEST(TileDealer, GivesEachTileOnceInScanOrderThenNone) {
  TileDealer d(3);
  EXPECT_EQ(d.request(1), 0u);
  EXPECT_EQ(d.request(0), 1u);
  EXPECT_EQ(d.left(), 1u);
  EXPECT_EQ(d.request(1), 2u);
  EXPECT_EQ(d.request(0), std::nullopt);  // asked just as the last tile went: nothing twice
  EXPECT_EQ(d.request(1), std::nullopt);
  EXPECT_EQ(d.owners(), (std::vector<int>{1, 0, 1}));
}

// PEs of different speeds each take a tile, then ask again when done with it (ties by PE): every
// pixel is rendered exactly once, the per-PE counts sum to the frame, and the fast PE does more.
TEST(TileDealer, OnDemandEveryPixelExactlyOnce) {
  const int w = 37, h = 23, edge = 5, pes = 3;  // 8 x 5 = 40 tiles for 3 PEs; edge tiles cut
  const auto tiles = screen_tiles(w, h, edge);
  ASSERT_EQ(tiles.size() % pes, 1u);
  const uint64_t cost_per_pixel[pes] = {1, 1, 4};
  TileDealer d(tiles.size());
  using Ask = std::pair<uint64_t, int>;  // (when, PE): the earliest first, then by PE
  std::priority_queue<Ask, std::vector<Ask>, std::greater<Ask>> asks;
  for (int pe = 0; pe < pes; ++pe) asks.push({0, pe});
  std::vector<int> seen(size_t(w * h), 0);
  std::vector<uint64_t> pe_pixels(pes, 0);
  while (!asks.empty()) {
    const auto [when, pe] = asks.top();
    asks.pop();
    const auto tile = d.request(pe);
    if (!tile) continue;
    for (uint32_t px : tile_pixels(tiles[*tile], w)) ++seen[px];
    pe_pixels[size_t(pe)] += tiles[*tile].pixels();
    asks.push({when + tiles[*tile].pixels() * cost_per_pixel[pe], pe});
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
  EXPECT_EQ(std::accumulate(pe_pixels.begin(), pe_pixels.end(), uint64_t(0)), uint64_t(w * h));
  EXPECT_GT(pe_pixels[0], 2 * pe_pixels[2]);
  EXPECT_EQ(d.left(), 0u);
  EXPECT_TRUE(std::none_of(d.owners().begin(), d.owners().end(), [](int o) { return o < 0; }));
}

}  // namespace
}  // namespace rtm
