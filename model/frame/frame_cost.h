// A frame's cost (cost/unit_cost.h) from a finished run's counters: the one place that reads
// MachineResult for it.
#pragma once

#include <cstdint>

#include "cost/unit_cost.h"
#include "frame/machine_result.h"

namespace rtm {

/// What the frame did, over all PEs, as the cost reads it; `pixels`: the frame's.
FrameActivity frame_activity(const MachineResult& m, const MachineConfig& c, uint64_t pixels);

/// The machine's area and the frame's energy in technology t, for a scene of `primitives`.
MachineCost frame_cost(const MachineResult& m, const MachineConfig& c, uint64_t pixels,
                       uint64_t primitives, const Technology& t);

}  // namespace rtm
