// The bytes each memory request moves, and the address it names: the records a PE's local memory
// holds, record by record. The sections they lie in, and the records the host's transfers move
// (kRayRecordBytes, kCameraRecordBytes, kPixelRecordBytes, kSpillRecordBytes), are those of
// memory/memory_layout.h; this adds what the units read and write of them, and where each record
// starts, so the memory timing's banks see the strides the data really has. A number is a machine
// word: 4 bytes in fp32, 8 in fp64 (the MAC, root unit and clip arithmetic); offsets and ids are
// 4 bytes. The sums are SceneImage's and memory_layout's own (tested).
#pragma once

#include <cstdint>
#include <vector>

#include "geom/mac_schedule.h"
#include "config/config.h"
#include "memory/memory_layout.h"

namespace rtm {

struct SceneImage;

constexpr uint64_t word_bytes(Precision p) { return p == Precision::Fp32 ? 4 : 8; }

// ---- Voxel data: which primitives lie in each voxel (Grid::start, Grid::items) ----

/// Per voxel, where its list of primitive ids begins; one more after the last voxel.
constexpr uint64_t kVoxelOffsetBytes = 4;
constexpr uint64_t kPrimitiveIdBytes = 4;
/// What a search unit reads to examine a voxel: its offset and the next one (where its list ends),
/// side by side; they differ exactly when the voxel is occupied.
constexpr uint64_t voxel_entry_bytes() { return 2 * kVoxelOffsetBytes; }
/// What an intersection lane reads of a voxel's list of `count` primitives.
constexpr uint64_t voxel_list_bytes(uint64_t count) { return count * kPrimitiveIdBytes; }
constexpr uint64_t voxel_data_bytes(uint64_t voxels, uint64_t references) {
  return kVoxelOffsetBytes * (voxels + 1) + kPrimitiveIdBytes * references;
}
/// PE cycles to build the voxel data itself (voxelisation = pe): `per_reference` cycles a
/// primitive reference registered (its voxel found and its id written), and the voxel offsets
/// written `bytes_per_cycle` at a time.
constexpr uint64_t pe_voxelisation_cycles(uint64_t per_reference, uint64_t bytes_per_cycle,
                                          uint64_t voxels, uint64_t references) {
  return per_reference * references +
         (kVoxelOffsetBytes * (voxels + 1) + bytes_per_cycle - 1) / bytes_per_cycle;
}

// ---- Primitive, light and material data ----

/// Words of a primitive's coefficient RAM image (the MAC's RAM, §5.2): the 13 of the full schedule
/// (A … J and the pre-scaled 2A, 2B, 2C), or with sparse schedules its non-zero words and a mask.
template <class Real>
uint64_t coef_record_words(const CoefRam<Real>& ram, bool sparse) {
  if (!sparse) return kRamWords;
  uint64_t words = 1;
  for (const Real& w : ram) words += w != 0;
  return words;
}
/// What a lane loads into its MAC's coefficient RAM on a miss (memory/coefficient_ram.h).
constexpr uint64_t coef_record_bytes(Precision p, uint64_t words = kRamWords) {
  return words * word_bytes(p);
}
/// A primitive's whole record, in words: its coefficient record, 3 for its centre, 4 per clip
/// half-space, 6 for its bounds and 1 for its material.
constexpr uint64_t primitive_record_words(uint64_t coef_words, uint64_t clips) {
  return coef_words + 3 + 4 * clips + 6 + 1;
}
/// Position and colour.
constexpr uint64_t kLightRecordWords = 6;
/// Colour, ka, kd, ks, kt and the index of refraction.
constexpr uint64_t kMaterialRecordWords = 8;

// ---- Pixels ----

/// The part of a frame-buffer entry (kPixelRecordBytes) shading reads, adds to and writes back:
/// the RGB, without the primitive id.
constexpr uint64_t kBrightnessBytes = kPixelRecordBytes - kPrimitiveIdBytes;

// ---- The host's transfers ----

/// What the PE's network interface writes into local memory at once of a transfer coming in: a
/// burst of 16 beats at the default port width (units/pe_memory.h, "The host's traffic").
constexpr uint64_t kHostBurstBytes = 64;
/// A streamed gather's transfer (gather = streamed): this header, the block's first pixel slot,
/// then the block's frame-buffer entries (kPixelRecordBytes each).
constexpr uint64_t kGatherBlockHeaderBytes = 4;
/// A streamed gather's transfer of `pixels` slots.
constexpr uint64_t gather_block_bytes(uint64_t pixels) {
  return kGatherBlockHeaderBytes + pixels * kPixelRecordBytes;
}

// ---- Where each record starts ----

/// The addresses of a PE's local memory, from 0 in the order of memory_layout's sections:
/// primitives (each one's record, its coefficient record first), voxel data (the offsets, then the
/// lists), lights and materials, primary rays, frame buffer; then the spill area.
struct MemoryAddresses {
  std::vector<uint64_t> primitives;  ///< each primitive's record; its coefficient record is there
  uint64_t voxel_offsets = 0, voxel_lists = 0;
  uint64_t lights = 0;  ///< the lights, then the materials
  uint64_t rays = 0;    ///< the primary rays (or the camera descriptor)
  uint64_t frame = 0;   ///< the frame buffer, kPixelRecordBytes a pixel slot
  uint64_t spill = 0;   ///< the spill area, kSpillRecordBytes a ray

  /// For `pixels` pixels, as memory_layout(image, pixels, c) lays them out.
  MemoryAddresses(const SceneImage& image, uint64_t pixels, const MachineConfig& c);

  uint64_t coef_record(uint32_t prim) const { return primitives[prim]; }
  uint64_t voxel_entry(int64_t voxel) const {
    return voxel_offsets + kVoxelOffsetBytes * uint64_t(voxel);
  }
  /// The list of a voxel whose offset is `first` (Grid::start[v]).
  uint64_t voxel_list(uint32_t first) const { return voxel_lists + kPrimitiveIdBytes * first; }
  uint64_t primary_ray(uint64_t i) const { return rays + kRayRecordBytes * i; }
  uint64_t frame_entry(uint64_t slot) const { return frame + kPixelRecordBytes * slot; }
  /// The k-th place of the spill area.
  uint64_t spilled_ray(uint64_t k) const { return spill + kSpillRecordBytes * k; }
};

}  // namespace rtm
