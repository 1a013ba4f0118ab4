// Every kind of unit of a PE, once, in rank order (units/unit_kind.h): its name, how many a PE
// has, the longest one item can take in it, and whether it counts towards utilisation and the
// bottleneck. Which FIFOs it reads and writes is the FIFO table's (units/fifo_table.h), which
// inputs() and outputs() read. The counters (units/pe_state.h), the frame statistics and the
// bottleneck (frame/frame_stats.*), the stats file (tb/stats_json.cpp), the stall watchdog
// (machine/machine.cpp), the event log and both schedulers' lists of units iterate it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "config/config.h"
#include "units/fifo_table.h"
#include "units/unit_kind.h"

namespace rtm {

/// What bounds the cycles of one item, from the scene and its grid: the stall watchdog's figures.
struct ItemBounds {
  uint64_t fullest_voxel = 0;  ///< the most primitives in one voxel
  uint64_t most_clips = 0;     ///< the most clip half-spaces of one primitive
  uint64_t lights = 0;
  uint64_t walk_voxels = 0;  ///< the most voxels one walk can pass (the grid's edges summed, and 3)
  uint64_t access = 0;       ///< one local-memory access at its slowest, behind every requester's
};

struct UnitSpec {
  UnitKind kind;
  const char* name;       ///< in statistics, the event log, waveforms and the docs
  const char* label;      ///< as people read it, in the printed summary ("root/sort")
  const char* count_key;  ///< the configuration key of how many a PE has; null: one
  int MachineConfig::*count;
  /// Root units rank (and are logged) by their lane: each takes only its own MAC's results.
  bool ranked_by_lane;
  /// The event log numbers it (mac0, root1); replicated units that are interchangeable (the
  /// search units: which takes a ray is the scheduler's choice) go unnumbered.
  bool logged_by_number;
  /// Counts towards utilisation, the frame profile and the bottleneck (frame/frame_stats.h).
  bool in_utilisation;
  /// An upper bound on the PE cycles the unit spends on one item without finishing it.
  uint64_t (*longest_item)(const MachineConfig&, const ItemBounds&);
  const char* doc;
};

/// In rank order: unit_table()[size_t(k)] is kind k's.
const std::array<UnitSpec, kUnitKinds>& unit_table();
inline const UnitSpec& unit_spec(UnitKind k) { return unit_table()[size_t(k)]; }
inline const char* unit_name(UnitKind k) { return unit_spec(k).name; }
/// How many units of kind k a PE of configuration c has.
inline int unit_count(UnitKind k, const MachineConfig& c) {
  const UnitSpec& u = unit_spec(k);
  return u.count ? c.*u.count : 1;
}
/// Every kind in the order a ray meets them along the macro-pipeline (Fig. 1): each after every
/// kind that writes a FIFO it reads, the FIFOs back into the front buffer aside; of the kinds
/// that may come next, the first in rank order.
std::vector<UnitKind> pipeline_order();
/// The FIFOs kind k reads, and writes, in the FIFO table's order.
std::vector<FifoId> inputs(UnitKind k);
std::vector<FifoId> outputs(UnitKind k);
/// How many of FIFO f a PE of configuration c has: one per unit of its writer's kind if per
/// lane, else one.
int fifo_count(const FifoSpec& f, const MachineConfig& c);

}  // namespace rtm
