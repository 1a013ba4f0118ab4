// The frame's derived statistics: utilisation, the frame profile and its bottleneck, the MAC
// bound, computed once from the counters of a run. The command line only prints and serialises them.
#pragma once

#include <string>

#include "machine/bottleneck.h"

namespace rtm {

struct MachineConfig;
struct MachineResult;

/// Busy fraction of each PE unit over the whole frame, averaged over the PEs.
using FrameUtilisation = UnitShares;

struct FrameStats {
  FrameUtilisation utilisation;  ///< over the frame
  FrameProfile profile;          ///< phases, utilisation over the PEs' working windows, stalls, imbalance
  std::string bottleneck;        ///< bottleneck(profile)
  /// Total MAC products / PEs, rounded up: the frame can't be shorter on a one-product-per-cycle MAC.
  double mac_bound_cycles = 0;
  double cycles_over_mac_bound = 0;  ///< 0 when there were no MAC products
};

/// The derived statistics of a finished run (run_machine fills MachineResult::stats with them).
FrameStats frame_stats(const MachineResult& m, const MachineConfig& c);

}  // namespace rtm
