// Where the cycles go: the phases of a frame and the unit that limits it, from the counters.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "units/unit_kind.h"

namespace rtm {

/// A fraction per kind of PE unit, by UnitKind (replicated units: per unit, so 1 is every unit,
/// all the time). Only the kinds the unit table counts towards utilisation are filled in.
struct UnitShares {
  std::array<double, kUnitKinds> of{};
  double& operator[](UnitKind k) { return of[size_t(k)]; }
  double operator[](UnitKind k) const { return of[size_t(k)]; }
};

struct FrameProfile {
  double total = 0;            ///< the frame's cycles
  double host_preprocess = 0;  ///< the host's voxel and primary-ray generation (HostTimes::work)
  double transfer = 0;  ///< until the transfer is done, the rest: the host waiting for the link
  double pe = 0;        ///< the PEs' work: transfer done to the last PE done
  double gather = 0;    ///< frame buffers back to the host, after the last PE is done
  bool gather_streamed = false;  ///< gather = streamed: the rest of the gather overlapped the PEs
  /// voxelisation = pe: each PE's build of its voxel data before its first ray (part of the
  /// transfer and PE phases, not a phase of its own).
  double pe_voxelisation = 0;
  // Of the PEs' working windows, per unit (units/pipeline.h's UnitStats):
  UnitShares busy;       ///< holding any item
  UnitShares issue;      ///< its entry taken by an item's interval: how close it is to saturated
  UnitShares occupancy;  ///< mean items inside
  UnitShares starved;    ///< able to take an item, none there
  double credit_stall =
      0;  ///< fraction of the working windows the front buffer had rays but no credit
  double memory_wait =
      0;  ///< results' waits for local-memory data, summed over the units, per working-window cycle
  double memory_port =
      0;  ///< the busiest local-memory port's busy share of the frame (0: ideal memory)
  double memory_access =
      0;  ///< the units' reads' times over the item-cycles the units held: their share of the work
  double imbalance = 1;  ///< max / mean PE working window
  double tile_wait =
      0;  ///< fraction of the working windows a PE's loop was empty, waiting for a tile (dynamic)
  /// Several frames (frames > 1): total is a frame of the steady state, and host_preprocess,
  /// transfer (the busiest link's, gather included) and pe (the longest PE's work, its switches
  /// between frames apart) are each stage's time a frame: they overlap, and the longest sets the
  /// pace.
  bool pipelined = false;
};

/// Every verdict bottleneck() gives: host_preprocessing (voxel and primary-ray generation on the
/// host), interconnect (the link: the scene and rays to the PEs, frame buffers back),
/// pe_voxelisation (the PEs building their voxel data, voxelisation = pe), memory (the
/// PEs' local memory: results waiting for their data), each unit of the unit table that counts
/// towards utilisation (a PE unit whose entry is nearly always taken), loop_credits (too few rays
/// allowed in flight: back-pressure), waiting_for_tiles (partition = dynamic: the PEs idle while
/// their requests for tiles cross the link), load_imbalance (one PE works much longer than the
/// mean), latency (nothing saturated: the loop's latency with the rays available).
/// docs/stats.schema.json's enum is tested against this list.
const std::vector<std::string>& bottleneck_names();

struct Bottleneck {
  std::string name;    ///< one of bottleneck_names()
  std::string reason;  ///< one line: the figures that decided it
};

/// The unit or phase that limits the frame. Rules, in order: host pre-processing, the link and the
/// PEs' voxelisation together taking half the frame (the largest is named; with a streamed gather
/// the reason gives its tail apart); the units' reads of local
/// memory taking half their item-cycles, or results waiting for it half the working window
/// (summed over the units); a PE unit whose entry is taken
/// (`issue`) >= 60% of the working window (for an unpipelined unit the same as busy; a pipelined
/// one can hold items all the time and still take more); credit stalls >= 30%; imbalance >= 1.3;
/// the largest host/link/voxelisation share if >= 25%; else latency.
Bottleneck bottleneck(const FrameProfile& p);

}  // namespace rtm
