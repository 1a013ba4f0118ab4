// What the units of one PE share, apart from any scheduler: the configuration, the scene image
// in local memory and the memory's timing, the counters they fill in, ray numbering, and the event
// log.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "config/config.h"
#include "render/reference.h"
#include "render/shade.h"
#include "units/event_log.h"
#include "units/pe_memory.h"
#include "units/pipeline.h"
#include "memory/scene_image.h"
#include "units/unit_table.h"

namespace rtm {

/// Times are in SystemC time-resolution units (ticks, sc_time::value()).
struct PeCounters {
  TraceCounts counts;
  uint64_t mac_products = 0;
  uint64_t mac_products_saved =
      0;  ///< skipped by sparse schedules, against the paper's 28 per test
  uint64_t mac_cycles_saved =
      0;  ///< cycles of the MAC's entry (its jobs' intervals) saved by sparse schedules
  uint64_t spills = 0;
  /// Per kind of unit (units/unit_table.h), one per unit, each counted by its own pipeline
  /// (sized by size_for() before any pipeline counts into them).
  std::array<std::vector<UnitStats>, kUnitKinds> units;
  void size_for(const MachineConfig& c) {
    for (const UnitSpec& u : unit_table())
      units[size_t(u.kind)].resize(size_t(unit_count(u.kind, c)));
  }
  UnitStats& unit(UnitKind k, int index) { return units[size_t(k)].at(size_t(index)); }
  /// Kind k's figures summed over its units.
  UnitStats total(UnitKind k) const {
    UnitStats s;
    for (const UnitStats& u : units[size_t(k)]) s += u;
    return s;
  }
  /// Every unit's figures summed.
  UnitStats all() const {
    UnitStats s;
    for (const UnitSpec& u : unit_table()) s += total(u.kind);
    return s;
  }
  uint64_t start = 0;         ///< the first primary ray handed out
  uint64_t finish = 0;        ///< the last ray ended
  uint64_t credit_stall = 0;  ///< rays waiting but no credit to send them
  uint64_t tile_wait = 0;     ///< loop empty, waiting for a tile (partition = dynamic)
  uint64_t frame_wait = 0;    ///< loop empty between two frames (frames > 1)
  /// frames > 1: when each frame's last ray ended (its loop empty after its last primary ray).
  std::vector<uint64_t> frame_ends;
  uint64_t spill_overflow =
      0;  ///< rays waiting when they outgrew the spill area (0: they never did)
  uint64_t spill_overflow_at = 0;
};

/// Which optional units a PE elaborates (all of them unless the machine leaves out what the
/// scene cannot use).
struct PeUnits {
  bool spawn_path = true;   ///< spawn FIFO from shading back to the front buffer
  bool shadow_rays = true;  ///< shading's shadow-ray generator
  bool reflection = true;   ///< shading's reflected-ray generator
  bool refraction = true;   ///< shading's transmitted-ray generator

  /// Whether the PE has this FIFO: the spawn path is left out when the scene spawns no rays.
  bool has(const FifoSpec& f) const { return !f.spawn_path || spawn_path; }
  /// Whether shading can spawn rays of this kind.
  bool generates(RayKind k) const {
    return k == RayKind::Shadow ? shadow_rays : k == RayKind::Reflected ? reflection : refraction;
  }
};

struct PeState {
  int pe = 0;
  PeUnits units;
  MachineConfig config;
  uint64_t cycle = 1;                       ///< the PE clock period in ticks
  std::shared_ptr<const SceneImage> image;  ///< set when the scene transfer lands in local memory
  PeCounters counters;
  uint32_t next_ray_id = 0;
  EventLog* log = nullptr;  ///< null: no event log
  /// Rays the front buffer can hold: on chip, and in the spill area local memory leaves over
  /// (memory/memory_layout.h); and the most rays one ray's end can spawn (a shadow ray per light,
  /// a reflected and a transmitted ray), which new primary rays must leave room for.
  uint64_t spill_rays = UINT64_MAX;
  uint64_t spawn_fanout = 0;
  /// Its local memory's timing, records, coefficient RAMs and voxel cache (units/pe_memory.h), made
  /// with the machine; null where a unit is tested without one (its accesses then cost nothing).
  std::shared_ptr<PeMemory> memory;

  uint64_t cycles(uint64_t ticks) const { return ticks / cycle; }

  /// frames > 1: the PE's primary rays a frame (its pixels; 0: one frame). Its rays and pixel
  /// slots run on from frame to frame; in local memory each frame's lie where the first's do.
  uint64_t frame_rays = 0;
  /// frames > 1: what a PE does between two frames before the next one's first ray (voxelisation
  /// = pe: building that frame's voxel data), in ticks.
  uint64_t frame_switch = 0;
  /// Where pixel slot or primary ray `i` lies in local memory: its frame's copy is laid out as
  /// the first frame's (memory/memory_layout.h).
  uint64_t place_in_frame(uint64_t i) const { return frame_rays ? i % frame_rays : i; }

  /// Per pixel slot of the PE: its rays made and not yet ended, and when the last one ended (the
  /// pixel's final brightness is in the frame buffer from then: gather = streamed sends it). Kept
  /// only for its readers, a streamed gather and a run of several frames (gathered once the run
  /// is over): every ray's put passes here.
  std::vector<uint32_t> pixel_rays;
  std::vector<uint64_t> pixel_done;
  bool tracks_pixels() const {
    return config.gather == MachineConfig::Gather::Streamed || frame_rays > 0;
  }
  /// `n` more rays of pixel `slot` are made (a primary ray; the rays a shaded one spawns).
  void rays_made(uint32_t slot, size_t n) {
    if (!tracks_pixels()) return;
    if (slot >= pixel_rays.size()) {
      pixel_rays.resize(size_t(slot) + 1, 0);
      pixel_done.resize(size_t(slot) + 1, 0);
    }
    pixel_rays[slot] += uint32_t(n);
  }
  /// A ray of pixel `slot` left the loop at `now`.
  void ray_ended(uint32_t slot, uint64_t now) {
    if (tracks_pixels() && slot < pixel_rays.size() && pixel_rays[slot] > 0 &&
        --pixel_rays[slot] == 0)
      pixel_done[slot] = now;
  }
};

}  // namespace rtm
