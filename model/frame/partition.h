// Screen partitioning: which pixels each PE renders (paper §1: the screen is split among PEs).
#pragma once

#include <cstdint>
#include <vector>

#include "config/config.h"

namespace rtm {

/// For each PE, its pixels (y * width + x) in scan order. Every pixel belongs to exactly one PE.
///  scanlines: row y goes to PE y mod N (interleaved rows);
///  blocks:    tile × tile blocks in scan order, dealt to PEs round robin;
///  strips:    contiguous bands of rows, as equal as possible;
///  pixels:    pixel (x, y) goes to PE (x + s·y) mod N, s ≈ 0.618 N: every PE gets every N-th
///             pixel of every row, the rows sheared against each other so a PE's pixels spread
///             over the whole screen (the finest static balance);
///  dynamic:   none yet: the host hands out tile × tile tiles as the PEs ask (frame/tiles.h).
std::vector<std::vector<uint32_t>> partition_screen(int width, int height, const MachineConfig& c);

/// How many PEs partition_screen leaves without a pixel (more PEs than rows, tiles or pixels); of
/// a dynamic partition, those beyond the tiles (each PE gets a tile up front while any are left).
int pes_without_pixels(int width, int height, const MachineConfig& c);

}  // namespace rtm
