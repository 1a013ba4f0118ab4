#include "units/scene_image.h"

namespace rtm {

SceneImage::SceneImage(const Scene& s, const Grid& g, const MachineConfig& c) : scene(&s), grid(&g) {
  const bool sparse = c.mac_schedule == MachineConfig::MacSchedule::Sparse;
  if (c.precision == Precision::Fp32) {
    mem32.emplace(s, g, c.recentre, c.numerics());
    if (sparse) mem32->use_sparse_schedule();
  } else {
    mem64.emplace(s, g, c.recentre, c.numerics());
    if (sparse) mem64->use_sparse_schedule();
  }
  // The bytes a PE's local memory holds, in the machine's word size: per primitive its
  // coefficient RAM words (13; with sparse schedules only the non-zero ones plus a mask word),
  // 3 for its centre, 4 per clip half-space, 6 for its bounds and one for its material; the
  // voxel data (one offset per voxel plus one id per reference); per light 6 words, per
  // material 8.
  const uint64_t word = mem32 ? 4 : 8;
  primitive_bytes = word * visit([&](const auto& mem) {
    uint64_t words = 0;
    for (size_t i = 0; i < s.primitives.size(); ++i) {
      uint64_t ram = kRamWords;
      if (sparse) {
        ram = 1;
        for (int w = 0; w < kRamWords; ++w) ram += mem.rams[i][size_t(w)] != 0;
      }
      words += ram + 3 + 4 * s.primitives[i].clips.size() + 6 + 1;
    }
    return words;
  });
  voxel_bytes = 4 * (uint64_t(g.start.size()) + uint64_t(g.items.size()));
  light_bytes = word * (6 * uint64_t(s.lights.size()) + 8 * uint64_t(s.materials.size()));
  bytes = primitive_bytes + voxel_bytes + light_bytes;
}

}  // namespace rtm
