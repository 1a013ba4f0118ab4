// The occupancy maps against the grid's voxel lists, counted voxel by voxel.
#include "geom/occupancy.h"

#include <gtest/gtest.h>

#include <random>

namespace rtm {
namespace {

/// A grid whose voxel lists hold one dummy item where `occupied` says so.
Grid grid_with(const std::array<int, 3>& n, const std::vector<bool>& occupied) {
  Grid g;
  g.n = n;
  g.start.assign(occupied.size() + 1, 0);
  for (size_t v = 0; v < occupied.size(); ++v) {
    g.start[v + 1] = g.start[v] + (occupied[v] ? 1 : 0);
    if (occupied[v]) g.items.push_back(0);
  }
  return g;
}

bool brute_empty(const Grid& g, const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x)
        if (g.count(g.index(x, y, z))) return false;
  return true;
}

/// Clusters of occupied voxels in empty space, on grids whose sizes are not powers of two.
Grid random_grid(std::mt19937& rng) {
  const std::array<int, 3> n{1 + int(rng() % 70), 1 + int(rng() % 70), 1 + int(rng() % 20)};
  std::vector<bool> occ(size_t(n[0]) * n[1] * n[2], false);
  const int clusters = int(rng() % 4);
  for (int c = 0; c < clusters; ++c) {
    const int cx = int(rng() % n[0]), cy = int(rng() % n[1]), cz = int(rng() % n[2]),
              r = int(rng() % 4);
    for (int z = std::max(0, cz - r); z <= std::min(n[2] - 1, cz + r); ++z)
      for (int y = std::max(0, cy - r); y <= std::min(n[1] - 1, cy + r); ++y)
        for (int x = std::max(0, cx - r); x <= std::min(n[0] - 1, cx + r); ++x)
          if (rng() % 3 == 0) occ[size_t((int64_t(z) * n[1] + y) * n[0] + x)] = true;
  }
  return grid_with(n, occ);
}

TEST(Occupancy, VoxelBitsFollowTheVoxelLists) {
  std::mt19937 rng(3);
  for (int i = 0; i < 20; ++i) {
    const Grid g = random_grid(rng);
    const Occupancy occ(g);
    for (int64_t v = 0; v < g.voxel_count(); ++v) ASSERT_EQ(occ.voxel(v), g.count(v) != 0) << v;
  }
}

TEST(Occupancy, EmptyBlocksAreAlignedAndEmpty) {
  std::mt19937 rng(5);
  int found = 0;
  for (int i = 0; i < 20; ++i) {
    const Grid g = random_grid(rng);
    const Occupancy occ(g);
    for (int k = 0; k < 500; ++k) {
      const std::array<int, 3> c{int(rng() % g.n[0]), int(rng() % g.n[1]), int(rng() % g.n[2])};
      if (occ.voxel(g.index(c[0], c[1], c[2]))) continue;
      std::array<int, 3> lo, hi;
      if (!occ.empty_block(c, lo, hi)) {
        // Then the smallest block worth a skip around it holds something.
        std::array<int, 3> blo, bhi;
        const int size = 1 << Occupancy::kMinLevel;
        for (int a = 0; a < 3; ++a) {
          blo[a] = c[a] / size * size;
          bhi[a] = std::min(blo[a] + size - 1, g.n[a] - 1);
        }
        ASSERT_FALSE(brute_empty(g, blo, bhi));
        continue;
      }
      ++found;
      for (int a = 0; a < 3; ++a) {
        ASSERT_LE(lo[a], c[a]);
        ASSERT_GE(hi[a], c[a]);
        ASSERT_LT(hi[a], g.n[a]);
        if (hi[a] == g.n[a] - 1) continue;  // clipped by the grid
        const int size = hi[a] - lo[a] + 1;
        ASSERT_EQ(size & (size - 1), 0) << "not a power of two";
        ASSERT_GE(size, 1 << Occupancy::kMinLevel);
        ASSERT_EQ(lo[a] % size, 0) << "not aligned";
      }
      ASSERT_TRUE(brute_empty(g, lo, hi));
    }
  }
  EXPECT_GT(found, 1000);
}

TEST(Occupancy, BoxEmptyNeverCallsAnOccupiedBoxEmpty) {
  std::mt19937 rng(9);
  int empty = 0, boxes = 0;
  for (int i = 0; i < 20; ++i) {
    const Grid g = random_grid(rng);
    const Occupancy occ(g);
    for (int k = 0; k < 500; ++k) {
      std::array<int, 3> lo, hi;
      for (int a = 0; a < 3; ++a) {
        lo[a] = int(rng() % g.n[a]);
        hi[a] = lo[a] + int(rng() % (g.n[a] - lo[a]));
      }
      ++boxes;
      const bool e = occ.box_empty(lo, hi);
      empty += e;
      if (e) {
        ASSERT_TRUE(brute_empty(g, lo, hi));
      }
      // Boxes made of whole counting blocks are answered exactly.
      const int s = 1 << Occupancy::kSumLevel;
      for (int a = 0; a < 3; ++a) {
        lo[a] = lo[a] / s * s;
        hi[a] = std::min((hi[a] / s + 1) * s - 1, g.n[a] - 1);
      }
      ASSERT_EQ(occ.box_empty(lo, hi), brute_empty(g, lo, hi));
    }
  }
  EXPECT_GT(empty, boxes / 10);
  EXPECT_LT(empty, boxes);
}

}  // namespace
}  // namespace rtm
