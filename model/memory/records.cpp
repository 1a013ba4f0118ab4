#include "memory/records.h"

#include <stdexcept>

#include "memory/scene_image.h"

namespace rtm {

MemoryAddresses::MemoryAddresses(const SceneImage& image, uint64_t pixels, const MachineConfig& c) {
  const MemoryLayout layout = memory_layout(image, pixels, c);
  if (layout.sections.size() != (c.frames > 1 ? 6 : 5))
    throw std::logic_error("memory addresses: memory_layout's sections changed");
  std::vector<uint64_t> start;
  uint64_t at = 0;
  for (const MemorySection& s : layout.sections) {
    start.push_back(at);
    at += s.bytes;
  }
  const bool sparse = c.mac_schedule == MachineConfig::MacSchedule::Sparse;
  const uint64_t word = word_bytes(c.intersection_precision_in_force());
  image.visit([&](const auto& mem) {
    uint64_t record = start[0];
    for (size_t i = 0; i < mem.rams.size(); ++i) {
      primitives.push_back(record);
      record += word * primitive_record_words(coef_record_words(mem.rams[i], sparse),
                                              image.scene->primitives[i].clips.size());
    }
  });
  voxel_offsets = start[1];
  voxel_lists = voxel_offsets + kVoxelOffsetBytes * image.grid->start.size();
  lights = start[2];
  rays = start[3];
  frame = start[4];
  spill = at;
}

}  // namespace rtm
