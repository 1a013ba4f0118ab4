#include "memory/scene_image.h"

#include "memory/records.h"

namespace rtm {

SceneImage::SceneImage(const Scene& s, const Grid& g, const MachineConfig& c)
    : scene(&s), grid(&g) {
  const bool sparse = c.mac_schedule == MachineConfig::MacSchedule::Sparse;
  if (c.intersection_precision_in_force() == Precision::Fp32) {
    mem32.emplace(s, g, c.recentre, c.numerics());
    if (sparse) mem32->use_sparse_schedule();
  } else {
    mem64.emplace(s, g, c.recentre, c.numerics());
    if (sparse) mem64->use_sparse_schedule();
  }
  // The bytes a PE's local memory holds, in the word size of the unit that reads them: per
  // primitive its coefficient RAM words (13; with sparse schedules only the non-zero ones plus a
  // mask word), 3 for its centre, 4 per clip half-space, 6 for its bounds and one for its
  // material, in the intersection unit's; the voxel data (one offset per voxel plus one id per
  // reference); per light 6 words, per material 8, in the shading unit's.
  const uint64_t word = word_bytes(c.intersection_precision_in_force());
  const uint64_t normal_bytes = c.normal_interpolation == NormalInterpolation::Barycentric
                                    ? word_bytes(c.shading_precision_in_force()) * 12
                                    : 0;
  primitive_record_bytes.resize(s.primitives.size());
  visit([&](const auto& mem) {
    for (size_t i = 0; i < s.primitives.size(); ++i) {
      uint64_t ram = kRamWords;
      if (sparse) {
        ram = 1;
        for (int w = 0; w < kRamWords; ++w) ram += mem.rams[i][size_t(w)] != 0;
      }
      const Primitive& p = s.primitives[i];
      // With barycentric normals, a triangle with vertex normals also holds them (9 words) and
      // the reciprocals of its clips' values at the opposite corners (3), in the shading unit's
      // words.
      primitive_record_bytes[i] = uint32_t(word * (ram + 3 + 4 * p.clips.size() + 6 + 1) +
                                           (p.normals.empty() ? 0 : normal_bytes));
      primitive_bytes += primitive_record_bytes[i];
    }
  });
  voxel_bytes = 4 * (uint64_t(g.start.size()) + uint64_t(g.items.size()));
  light_bytes = word_bytes(c.shading_precision_in_force()) *
                (6 * uint64_t(s.lights.size()) + 8 * uint64_t(s.materials.size()));
  bytes = primitive_bytes + voxel_bytes + light_bytes;
}

}  // namespace rtm
