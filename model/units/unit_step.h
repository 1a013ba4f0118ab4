// One wake-up of a unit, the same under both schedulers: write the results that are due (once
// their data from local memory is there), take the next item if the unit can, then say what to
// wake it for. Each scheduler supplies every operation on its own FIFOs and clock:
//   void woke(now)        the unit was woken, for whatever reason: a wait for input is over
//   bool write_head(now)  writes the head item's results; false when a FIFO is full
//   void retired(item)    the head item has left the unit
//   bool accept(now)      takes the next item (Pipeline::accept); false when there is none
//   bool wait_for_input() wake me when an input arrives; false when the unit does not wait after
//                         all (the front buffer aligning to a clock edge, or finished)
//   void want(t)          wake me at t (a repeated time is one wake-up: units/wakeups.h)
// The front buffer's accept is FrontBufferPolicy::carry_out (units/front_buffer.h), with its own
// operations; shading writes its outputs through ShadingWriter (units/shading_unit.h).
#pragma once

#include <cstdint>

#include "units/pipeline.h"

namespace rtm {

/// Returns whether the unit now waits for input.
template <class Item, class Ops>
bool step_unit(Pipeline<Item>& pipe, uint64_t now, uint64_t cycle, PeMemory* memory, Ops& ops) {
  ops.woke(now);
  pipe.woke(now);
  bool waiting = false;
  for (;;) {
    while (!pipe.empty() && pipe.head().due <= now) {
      // Data from local memory that comes after the result is due stalls the pipeline until it
      // is there, as a full FIFO does (units/pe_memory.h).
      if (auto& h = pipe.head(); memory && !h.wait.empty())
        if (const uint64_t at = memory->ready(h.wait, h.accepted, h.due, now, cycle); at > now) {
          ops.want(at);
          return false;
        }
      // A full FIFO stalls the pipeline: try again next cycle, as a hardware handshake would.
      if (!ops.write_head(now)) {
        ops.want(now + cycle);
        return false;
      }
      ops.retired(pipe.retire(now));
    }
    if (!pipe.can_accept(now)) break;
    if (!ops.accept(now)) {
      pipe.starve(now);
      waiting = ops.wait_for_input();
      break;
    }
    // An item without latency is done at once: go round again.
  }
  if (!pipe.empty()) ops.want(pipe.head().due);
  // Unpipelined, the next item may come when the result leaves: one wake-up for both.
  if (pipe.ready() > now && (pipe.empty() || pipe.ready() != pipe.head().due))
    ops.want(pipe.ready());
  return waiting;
}

}  // namespace rtm
