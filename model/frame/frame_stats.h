// The frame's derived statistics: utilisation, the frame profile and its bottleneck, the MAC
// bound, computed once from the counters of a run. The command line only prints and serialises
// them.
#pragma once

#include <string>
#include <vector>

#include "frame/bottleneck.h"

namespace rtm {

struct MachineConfig;
struct MachineResult;

/// Busy fraction of each PE unit over the whole frame, averaged over the PEs.
using FrameUtilisation = UnitShares;

/// One search unit's shares of its PE's working window (units/pipeline.h's UnitStats).
struct SearchUnitShares {
  double busy = 0;   ///< holding any item
  double issue = 0;  ///< its entry taken by an item's interval
};

struct FrameStats {
  FrameUtilisation utilisation;  ///< over the frame
  FrameProfile profile;  ///< phases, utilisation over the PEs' working windows, stalls, imbalance
  /// Per PE, each search unit on its own: the profile's mean hides a last unit that never works.
  std::vector<std::vector<SearchUnitShares>> search_units;
  Bottleneck bottleneck;  ///< bottleneck(profile)
  /// Total MAC products / PEs, rounded up: the frame can't be shorter on a one-product-per-cycle
  /// MAC.
  double mac_bound_cycles = 0;
  double cycles_over_mac_bound = 0;  ///< 0 when there were no MAC products
};

/// The derived statistics of a finished run (run_machine fills MachineResult::stats with them).
FrameStats frame_stats(const MachineResult& m, const MachineConfig& c);

}  // namespace rtm
