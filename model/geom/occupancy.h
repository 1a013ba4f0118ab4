// Which voxels of a grid hold anything, at several scales: lets a walk cross empty space in
// large steps (Dda::skip_box) while visiting exactly the voxels the one-voxel walk visits.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "geom/grid.h"

namespace rtm {

class Occupancy {
 public:
  /// Level L groups the grid into aligned blocks of 2^L voxels a side.
  static constexpr int kLevels = 6;
  /// Blocks below this level are not worth a skip: stepping through them is cheaper (measured on
  /// SPD balls-4, rings-7 and tree-11).
  static constexpr int kMinLevel = 3;
  /// Occupied blocks of this level are also counted in a summed-volume table, so any box of
  /// cells can be asked whether it is empty in eight reads.
  static constexpr int kSumLevel = 2;

  explicit Occupancy(const Grid& g) : n_(g.n) {
    for (int level = 0; level <= kLevels; ++level) {
      for (int a = 0; a < 3; ++a) dims_[level][a] = ((g.n[a] - 1) >> level) + 1;
      bits_[level].assign(
          size_t(dims_[level][0] * int64_t(dims_[level][1]) * dims_[level][2] + 63) / 64, 0);
    }
    for (int z = 0; z < g.n[2]; ++z)
      for (int y = 0; y < g.n[1]; ++y)
        for (int x = 0; x < g.n[0]; ++x)
          if (g.count(g.index(x, y, z)) != 0)
            for (int level = 0; level <= kLevels; ++level)
              set(level, {x >> level, y >> level, z >> level});
    const auto& nb = dims_[kSumLevel];
    for (int a = 0; a < 3; ++a) sdim_[a] = size_t(nb[a]) + 1;
    sums_.assign(sdim_[0] * sdim_[1] * sdim_[2], 0);
    for (int z = 1; z <= nb[2]; ++z)
      for (int y = 1; y <= nb[1]; ++y)
        for (int x = 1; x <= nb[0]; ++x)
          sums_[sum_index(x, y, z)] =
              uint32_t(get(kSumLevel, {x - 1, y - 1, z - 1})) + sums_[sum_index(x - 1, y, z)] +
              sums_[sum_index(x, y - 1, z)] + sums_[sum_index(x, y, z - 1)] -
              sums_[sum_index(x - 1, y - 1, z)] - sums_[sum_index(x - 1, y, z - 1)] -
              sums_[sum_index(x, y - 1, z - 1)] + sums_[sum_index(x - 1, y - 1, z - 1)];
  }

  /// Does voxel v (Grid::index) hold any primitive?
  bool voxel(int64_t v) const { return bits_[0][size_t(v) >> 6] >> (v & 63) & 1; }

  /// The largest empty aligned block holding `cell` (an empty voxel), clipped to the grid, as a
  /// box of cells [lo, hi]; false if no block of kMinLevel or more around it is empty.
  bool empty_block(const std::array<int, 3>& cell, std::array<int, 3>& lo,
                   std::array<int, 3>& hi) const {
    int level = kMinLevel;
    if (get(level, {cell[0] >> level, cell[1] >> level, cell[2] >> level})) return false;
    while (level < kLevels && !get(level + 1, {cell[0] >> (level + 1), cell[1] >> (level + 1),
                                               cell[2] >> (level + 1)}))
      ++level;
    for (int a = 0; a < 3; ++a) {
      lo[a] = cell[a] >> level << level;
      hi[a] = std::min(lo[a] + (1 << level) - 1, n_[a] - 1);
    }
    return true;
  }

  /// Is every voxel of the box of cells [lo, hi] empty? (Asked of the blocks holding it, so a
  /// box that merely touches an occupied block counts as occupied.)
  bool box_empty(const std::array<int, 3>& lo, const std::array<int, 3>& hi) const {
    const int s = kSumLevel;
    const size_t x0 = size_t(lo[0] >> s), y0 = size_t(lo[1] >> s), z0 = size_t(lo[2] >> s);
    const size_t x1 = size_t(hi[0] >> s) + 1, y1 = size_t(hi[1] >> s) + 1,
                 z1 = size_t(hi[2] >> s) + 1;
    const uint32_t total = sums_[sum_index(x1, y1, z1)] - sums_[sum_index(x0, y1, z1)] -
                           sums_[sum_index(x1, y0, z1)] - sums_[sum_index(x1, y1, z0)] +
                           sums_[sum_index(x0, y0, z1)] + sums_[sum_index(x0, y1, z0)] +
                           sums_[sum_index(x1, y0, z0)] - sums_[sum_index(x0, y0, z0)];
    return total == 0;
  }

 private:
  size_t bit(int level, const std::array<int, 3>& b) const {
    const auto& n = dims_[level];
    return (size_t(b[2]) * size_t(n[1]) + size_t(b[1])) * size_t(n[0]) + size_t(b[0]);
  }
  void set(int level, const std::array<int, 3>& b) {
    const size_t i = bit(level, b);
    bits_[level][i >> 6] |= uint64_t(1) << (i & 63);
  }
  bool get(int level, const std::array<int, 3>& b) const {
    const size_t i = bit(level, b);
    return bits_[level][i >> 6] >> (i & 63) & 1;
  }
  size_t sum_index(size_t x, size_t y, size_t z) const { return (z * sdim_[1] + y) * sdim_[0] + x; }

  std::array<int, 3> n_;
  std::array<std::array<int, 3>, kLevels + 1> dims_{};
  std::array<std::vector<uint64_t>, kLevels + 1> bits_;
  std::array<size_t, 3> sdim_{};
  std::vector<uint32_t> sums_;  ///< occupied level-kSumLevel blocks in [0, x) × [0, y) × [0, z)
};

}  // namespace rtm
