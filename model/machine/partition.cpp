#include "machine/partition.h"

#include <algorithm>

namespace rtm {

std::vector<std::vector<uint32_t>> partition_screen(int width, int height, const MachineConfig& c) {
  const int n = c.pes;
  // A shear near the golden ratio of N keeps a PE's pixels in neighbouring rows far apart.
  const int64_t shear = std::max<int64_t>(1, int64_t(0.6180339887 * n));
  std::vector<std::vector<uint32_t>> parts(static_cast<size_t>(n));
  auto pe_of = [&](int x, int y) -> int {
    switch (c.partition) {
      case Partition::Scanlines: return y % n;
      case Partition::Blocks: {
        const int tiles_x = (width + c.tile - 1) / c.tile;
        return int((int64_t(y / c.tile) * tiles_x + x / c.tile) % n);
      }
      case Partition::Strips: return int(int64_t(y) * n / height);
      case Partition::Pixels: return int((x + shear * y) % n);
    }
    return 0;
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) parts[size_t(pe_of(x, y))].push_back(uint32_t(y) * uint32_t(width) + uint32_t(x));
  return parts;
}

}  // namespace rtm
