// What a run of the machine for one frame gives: the image, the counters of every PE, FIFO and
// link, the host's phases and the figures derived from them, as plain values (times in ticks of
// SystemC's resolution, 1 ps), so that what reads a run needs no kernel.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "frame/frame_stats.h"
#include "memory/memory_layout.h"
#include "net/interconnect.h"
#include "render/reference.h"
#include "render/scene_needs.h"
#include "units/fifo_table.h"
#include "units/pe_memory.h"
#include "units/pe_state.h"

namespace rtm {

/// When each phase of the frame ended, in ticks.
struct HostTimes {
  uint64_t voxels = 0, rays = 0, transfer = 0, pes_done = 0, gathered = 0;
  uint64_t link_busy = 0;  ///< summed over the links
  /// The host's own work (voxel and primary-ray generation) before `transfer`; the rest of that
  /// time it waited for the link. The two differ from `rays` when the rays stream (ray_block > 0).
  uint64_t work = 0;
  /// voxelisation = pe: each PE's build of its voxel data, between its scene's arrival and its
  /// first ray (0: the host built it); with a streamed scene (scene_block > 0) the most any PE's
  /// build adds after its last block is in.
  uint64_t pe_voxelisation = 0;
  /// frames > 1: when each frame's pixels were all at the host.
  std::vector<uint64_t> frame_done;
};

/// Per FIFO kind, over all PEs.
struct FifoSummary {
  std::string kind;
  int depth = 0;
  int peak = 0;
  double mean = 0;  ///< time-weighted mean occupancy, averaged over the FIFOs of this kind
};

struct MachineResult {
  Image image;
  TraceCounts counts;
  uint64_t mac_products = 0, mac_busy_cycles = 0, mac_issue_cycles = 0, spills = 0;
  std::vector<PeCounters> per_pe;
  std::vector<uint32_t> tiles;  ///< partition = dynamic: the tiles each PE got (else empty)
  std::vector<FifoSummary> fifos;
  std::array<uint64_t, kFifoCount>
      fifo_writes{};  ///< records written into each FIFO of the table, over all PEs
  HostTimes host;
  uint64_t clock_ticks = 0;  ///< the PE clock period, in ticks of simulated time (1 ps)
  std::vector<LinkUse>
      links;  ///< the interconnect's links: busy time and bytes of each (net/interconnect.h)
  uint64_t scene_bytes = 0;  ///< one PE's copy of the scene as the link carries it
  /// voxelisation = pe: the primitives placed in the grids and the references registered, over
  /// all PEs (0: the host built the voxel data).
  uint64_t voxel_primitives = 0, voxel_references = 0;
  std::vector<MemoryLayout> memory;   ///< each PE's local memory (memory/memory_layout.h)
  std::vector<MemoryUse> memory_use;  ///< what each PE's local memory did (units/pe_memory.h)
  uint64_t end = 0;                   ///< the frame's simulated time, in ticks
  uint64_t cycles = 0;                ///< the frame's simulated time in PE cycles
  /// frames > 1: when each frame's pixels were all at the host, in PE cycles (else empty).
  std::vector<uint64_t> frame_done;
  /// A frame's time: with several frames the steady state's, the mean of every frame's after the
  /// first (which also fills the pipeline).
  double frame_cycles() const {
    const size_t n = frame_done.size();
    return n < 2 ? double(cycles) : double(frame_done[n - 1] - frame_done[0]) / double(n - 1);
  }
  FrameStats stats;  ///< derived from the counters above (frame_stats.h)
  double wall_seconds = 0;
  SceneNeeds needs;                         ///< what the scene can use (render/scene_needs.h)
  std::vector<std::string> left_out_units;  ///< per PE, not elaborated
  uint64_t mac_products_saved = 0,
           mac_cycles_saved = 0;   ///< by sparse MAC schedules (cycles: of the MAC's entry)
  PeUnits units;                   ///< what each PE elaborated
  std::string engine_unsupported;  ///< why the PEs ran as modules; empty: on the PE engine
  std::vector<std::string>
      warnings;  ///< for the user, one line each (e.g. a waveform window that recorded nothing)
  bool deadlock = false;
  std::string deadlock_report;  ///< every FIFO's occupancy when the simulation stalled
};

}  // namespace rtm
