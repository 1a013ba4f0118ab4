// Where the cycles go: the phases of a frame and the unit that limits it, from the counters.
#pragma once

#include <array>
#include <string>

namespace rtm {

/// A fraction per kind of PE unit (replicated units: per unit, so 1 is every unit, all the time).
struct UnitShares {
  double front_buffer = 0, search = 0, mac = 0, root = 0, shading = 0;
};

struct FrameProfile {
  double total = 0;             ///< the frame's cycles
  double host_preprocess = 0;   ///< voxel and primary-ray generation (overlapping transfers when streaming)
  double transfer = 0;          ///< scene and rays to the PEs, after pre-processing
  double pe = 0;                ///< the PEs' work: transfer done to the last PE done
  double gather = 0;            ///< frame buffers back to the host
  // Of the PEs' working windows, per unit (units/pipeline.h's UnitStats):
  UnitShares busy;       ///< holding any item
  UnitShares issue;      ///< its entry taken by an item's interval: how close it is to saturated
  UnitShares occupancy;  ///< mean items inside
  UnitShares starved;    ///< able to take an item, none there
  double credit_stall = 0;      ///< fraction of the working windows the front buffer had rays but no credit
  double imbalance = 1;         ///< max / mean PE working window
};

/// Every verdict bottleneck() gives, declared once: docs/stats.schema.json's enum is tested
/// against this list.
inline constexpr std::array<const char*, 10> kBottleneckNames = {
    "host_preprocessing",  // voxel and primary-ray generation on the host
    "interconnect",        // the link: the scene and rays to the PEs, frame buffers back
    "search", "mac", "root", "shading", "front_buffer",  // a PE unit whose entry is nearly always taken
    "loop_credits",    // too few rays allowed in flight: back-pressure
    "load_imbalance",  // one PE works much longer than the mean
    "latency",         // nothing saturated: the loop's latency with the rays available
};

struct Bottleneck {
  std::string name;    ///< one of kBottleneckNames
  std::string reason;  ///< one line: the figures that decided it
};

/// The unit or phase that limits the frame. Rules, in order: host pre-processing and the link
/// together taking half the frame (the larger of the two is named); a PE unit whose entry is taken
/// (`issue`) >= 60% of the working window (for an unpipelined unit the same as busy; a pipelined
/// one can hold items all the time and still take more); credit stalls >= 30%; imbalance >= 1.3;
/// the larger host/link share if >= 25%; else latency.
Bottleneck bottleneck(const FrameProfile& p);

}  // namespace rtm
