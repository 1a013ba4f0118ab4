#include "memory/memory_layout.h"

#include "memory/scene_image.h"

namespace rtm {

std::string MemoryLayout::describe() const {
  std::string s;
  for (const MemorySection& m : sections)
    s += (s.empty() ? "" : ", ") + m.name + " " + std::to_string(m.bytes) + " B";
  return s;
}

uint64_t ray_transfer_bytes(const MachineConfig& c, uint64_t rays, bool first) {
  if (c.ray_generation == MachineConfig::RayGeneration::Host) return rays * kRayRecordBytes;
  if (c.partition != Partition::Dynamic) return kCameraRecordBytes;
  return (first ? kCameraRecordBytes : 0) + kTileDescriptorBytes;
}

MemoryLayout memory_layout(const SceneImage& image, uint64_t pixels, const MachineConfig& c) {
  MemoryLayout m;
  m.capacity = uint64_t(c.local_memory_bytes);
  const bool pe_rays = c.ray_generation == MachineConfig::RayGeneration::Pe;
  // The program (§3.1) is not modelled: the units are hardwired.
  m.sections = {{"primitives", image.primitive_bytes},
                {"voxel data", image.voxel_bytes},
                {"lights and materials", image.light_bytes},
                {"primary rays", pe_rays ? kCameraRecordBytes : pixels * kRayRecordBytes},
                {"frame buffer", pixels * kPixelRecordBytes}};
  for (const MemorySection& s : m.sections) m.used += s.bytes;
  // Several frames: the next frame's scene and rays come, and the last one's frame buffer is
  // gathered, while the PE renders this one.
  if (c.frames > 1) {
    m.sections.push_back({"the next frame's copy of these", m.used});
    m.used *= 2;
  }
  return m;
}

size_t fullest_pe(const std::vector<MemoryLayout>& pes) {
  size_t fullest = 0;
  for (size_t i = 0; i < pes.size(); ++i)
    if (pes[i].used > pes[fullest].used) fullest = i;
  return fullest;
}

}  // namespace rtm
