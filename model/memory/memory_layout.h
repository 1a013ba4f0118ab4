// A PE's local memory as the paper fills it (§3.1: an identical copy of the primitive, voxel and
// light data in each PE), plus what the PE itself keeps there: its primary rays, its part of the
// frame buffer, and what is left over as the front buffer's spill area. Computed from the real
// data before simulation, so a scene that cannot fit is refused before it runs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rtm {

struct MachineConfig;
struct SceneImage;

/// Bytes the hardware would move for one primary ray: origin and direction as six words and a
/// pixel number.
constexpr uint64_t kRayRecordBytes = 28;
/// Bytes of the camera and screen-share descriptor a PE needs to generate its own primary rays.
constexpr uint64_t kCameraRecordBytes = 64;
/// partition = dynamic: a PE's request for its next tile (PE -> host) ...
constexpr uint64_t kTileRequestBytes = 4;
/// ... and the host's answer, a tile descriptor: x, y, width, height as 16-bit words (height 0:
/// no tile is left). With ray_generation = host the tile's ray records travel instead.
constexpr uint64_t kTileDescriptorBytes = 8;
/// Bytes per frame-buffer pixel (also what the gather moves): RGB as three floats and the
/// primitive id.
constexpr uint64_t kPixelRecordBytes = 16;
/// Bytes of a ray parked in the spill area: its primary-ray record, its walk (voxel index as
/// three words, the next plane crossing on each axis, the entry point) and its number: all a
/// search unit needs to carry on where it left off.
constexpr uint64_t kSpillRecordBytes = kRayRecordBytes + 4 * (3 + 3 + 1) + 4;

struct MemorySection {
  std::string name;
  uint64_t bytes = 0;
};

struct MemoryLayout {
  uint64_t capacity = 0;                ///< local_memory_bytes
  std::vector<MemorySection> sections;  ///< in address order; the spill area is not one of them
  uint64_t used = 0;                    ///< the sections' sum
  /// What is left: the spill area (0 when the sections do not fit).
  uint64_t spill_bytes() const { return used < capacity ? capacity - used : 0; }
  uint64_t spill_rays() const { return spill_bytes() / kSpillRecordBytes; }
  bool fits() const { return used <= capacity; }
  /// "primitives 123 B, voxel data 456 B, …" for messages.
  std::string describe() const;
};

/// Bytes of a transfer of `rays` primary rays to a PE, on the link and into its local memory: their
/// records; or, generating them on the PE, the camera record (with the PE's `first` transfer) and,
/// of a dynamic partition, the tile's descriptor.
uint64_t ray_transfer_bytes(const MachineConfig& c, uint64_t rays, bool first);

/// PE memory for `pixels` pixels and as many primary rays (one per pixel; with ray_generation =
/// pe only the camera descriptor).
MemoryLayout memory_layout(const SceneImage& image, uint64_t pixels, const MachineConfig& c);

/// The PE whose local memory holds the most (every PE has the same scene copy: the one with the
/// most pixels); the first of them on a tie. `pes` must not be empty.
size_t fullest_pe(const std::vector<MemoryLayout>& pes);

}  // namespace rtm
