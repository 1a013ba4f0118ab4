// A processing element as the host and the machine see it, however its pipeline is simulated:
// local memory on the host's link, the units' counters, and an event when its part of the frame
// is done. Two kinds: a PE as SystemC modules, one per block of paper Fig. 1 (modular_pe.h), and
// a PE whose units the PE engine schedules on its own event loop (engine_pe.h).
//
//   front buffer ─► search units (K) ─┬─► intersection units (M: MAC ► root/sort) ─┬─► shading
//        ▲  ▲  ▲                      │ empty voxel                      │ no hit   │ spawned rays
//        │  │  └──────────────────────┘                                  │          │
//        │  └────────────────────────────────────────────────────────────┘          │
//        └──────────────────────────────────────────────────────────────────────────┘
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <systemc>

#include "machine/local_memory.h"
#include "machine/metered_fifo.h"
#include "units/fifo_report.h"

namespace rtm {

class Pe : public sc_core::sc_module {
 public:
  PeContext ctx;
  LocalMemory memory;
  sc_core::sc_event finished_event;  ///< every ray of the PE's part of the frame has ended

  virtual bool finished() const = 0;
  /// Every FIFO, in the FIFO table's order (units/fifo_table.h), for statistics.
  virtual FifoStatsList fifo_stats() = 0;
  /// The front buffer's state and every FIFO's occupancy, for deadlock reports.
  virtual std::string occupancy_report() = 0;
  virtual void trace(Waveform& wave) = 0;

 protected:
  /// `pixels`: how many pixels of the screen this PE renders (partition = dynamic: 0, its tiles
  /// come as it asks for them).
  Pe(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units,
     size_t pixels, Timekeeper* keeper);
};

}  // namespace rtm
