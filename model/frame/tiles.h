// Tiles handed out on demand: the screen cut into tile × tile tiles that the host gives to
// whichever PE asks next, first come, first served, each tile once. Pure bookkeeping; the timing of
// the requests and descriptors is the interconnect's.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace rtm {

/// A rectangle of the screen, in pixels.
struct Tile {
  uint32_t x = 0, y = 0, width = 0, height = 0;
  uint64_t pixels() const { return uint64_t(width) * height; }
};

/// The screen's tiles of `edge` × `edge` pixels in scan order; those at the right and bottom edges
/// are cut to the screen.
std::vector<Tile> screen_tiles(int width, int height, int edge);

/// A tile's pixels (y · screen_width + x) in scan order.
std::vector<uint32_t> tile_pixels(const Tile& t, int screen_width);

/// Hands tiles out in scan order to the PEs that ask, each tile once, and remembers who got it.
class TileDealer {
 public:
  explicit TileDealer(size_t tiles) : owner_(tiles, -1) {}
  /// PE `pe` asks for a tile: the next one, or none once all are given out.
  std::optional<size_t> request(int pe);
  size_t left() const { return owner_.size() - next_; }
  /// Who got each tile (-1: not yet given out).
  const std::vector<int>& owners() const { return owner_; }

 private:
  std::vector<int> owner_;
  size_t next_ = 0;
};

}  // namespace rtm
