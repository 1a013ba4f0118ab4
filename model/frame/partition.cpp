#include "frame/partition.h"

#include <algorithm>

#include "frame/tiles.h"

namespace rtm {
namespace {

/// Calls `visit(pe, pixel)` for every pixel in scan order, with the PE it belongs to.
template <class Visit>
void deal_pixels(int width, int height, const MachineConfig& c, Visit visit) {
  const int n = c.pes;
  // A shear near the golden ratio of N keeps a PE's pixels in neighbouring rows far apart.
  const int64_t shear = std::max<int64_t>(1, int64_t(0.6180339887 * n));
  const int tiles_x = (width + c.tile - 1) / c.tile;
  auto pe_of = [&](int x, int y) -> int {
    switch (c.partition) {
      case Partition::Scanlines:
        return y % n;
      case Partition::Blocks:
        return int((int64_t(y / c.tile) * tiles_x + x / c.tile) % n);
      case Partition::Strips:
        return int(int64_t(y) * n / height);
      case Partition::Pixels:
        return int((x + shear * y) % n);
      case Partition::Dynamic:
        break;
    }
    return 0;
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) visit(pe_of(x, y), uint32_t(y) * uint32_t(width) + uint32_t(x));
}

}  // namespace

std::vector<std::vector<uint32_t>> partition_screen(int width, int height, const MachineConfig& c) {
  std::vector<std::vector<uint32_t>> parts(static_cast<size_t>(c.pes));
  if (c.partition == Partition::Dynamic) return parts;
  deal_pixels(width, height, c,
              [&](int pe, uint32_t pixel) { parts[size_t(pe)].push_back(pixel); });
  return parts;
}

int pes_without_pixels(int width, int height, const MachineConfig& c) {
  if (c.partition == Partition::Dynamic)
    return std::max(0, c.pes - int(screen_tiles(width, height, c.tile).size()));
  std::vector<bool> has(size_t(c.pes), false);
  deal_pixels(width, height, c, [&](int pe, uint32_t) { has[size_t(pe)] = true; });
  return int(std::count(has.begin(), has.end(), false));
}

}  // namespace rtm
