// A hand-built grid the unit tests share.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geom/grid.h"

namespace rtm::test {

/// A grid of unit voxels from the origin, n[0] x n[1] x n[2], whose voxels list `items`.
inline Grid unit_grid(std::array<int, 3> n, std::vector<uint32_t> items = {}) {
  Grid g;
  g.n = n;
  g.box = {{0, 0, 0}, {double(n[0]), double(n[1]), double(n[2])}};
  g.start.assign(size_t(n[0] * n[1] * n[2] + 1), 0);
  for (size_t v = 1; v < g.start.size(); ++v) g.start[v] = uint32_t(items.size());
  g.items = std::move(items);
  return g;
}

}  // namespace rtm::test
