#include "frame/tiles.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rtm {

std::vector<Tile> screen_tiles(int width, int height, int edge) {
  if (width < 1 || height < 1 || edge < 1)
    throw std::invalid_argument("screen_tiles: a " + std::to_string(width) + "x" +
                                std::to_string(height) + " screen in tiles of edge " +
                                std::to_string(edge));
  std::vector<Tile> tiles;
  for (int y = 0; y < height; y += edge)
    for (int x = 0; x < width; x += edge)
      tiles.push_back({uint32_t(x), uint32_t(y), uint32_t(std::min(edge, width - x)),
                       uint32_t(std::min(edge, height - y))});
  return tiles;
}

std::vector<uint32_t> tile_pixels(const Tile& t, int screen_width) {
  std::vector<uint32_t> pixels;
  pixels.reserve(size_t(t.pixels()));
  for (uint32_t y = t.y; y < t.y + t.height; ++y)
    for (uint32_t x = t.x; x < t.x + t.width; ++x) pixels.push_back(y * uint32_t(screen_width) + x);
  return pixels;
}

std::optional<size_t> TileDealer::request(int pe) {
  if (next_ == owner_.size()) return std::nullopt;
  owner_[next_] = pe;
  return next_++;
}

}  // namespace rtm
