// Where the cycles go: the phases of a frame and the unit that limits it, from the counters.
#pragma once

#include <string>

namespace rtm {

struct FrameProfile {
  double total = 0;             ///< the frame's cycles
  double host_preprocess = 0;   ///< voxel and primary-ray generation (overlapping transfers when streaming)
  double transfer = 0;          ///< scene and rays to the PEs, after pre-processing
  double pe = 0;                ///< the PEs' work: transfer done to the last PE done
  double gather = 0;            ///< frame buffers back to the host
  /// Busy fraction of each PE unit over the PEs' working windows (search: per unit).
  double search = 0, mac = 0, root = 0, shading = 0, front_buffer = 0;
  double credit_stall = 0;      ///< fraction of the working windows the front buffer had rays but no credit
  double imbalance = 1;         ///< max / mean PE working window
};

/// The bottleneck's name: host_preprocessing, interconnect, search, mac, root, shading,
/// front_buffer, loop_credits (too few rays allowed in flight: back-pressure), load_imbalance,
/// or latency (nothing saturated: the loop's latency with the rays available).
/// Rules, in order: host pre-processing and the link together taking half the frame (the larger
/// of the two is named); a PE unit busy >= 60% of
/// the working window; credit stalls >= 30%; imbalance >= 1.3; the largest host/link share if
/// >= 25%; else latency.
std::string bottleneck(const FrameProfile& p);

}  // namespace rtm
