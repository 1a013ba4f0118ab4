// A PE whose units the PE engine (pe_engine.h) schedules on its own event loop instead of one
// SystemC process per unit. To the host it is the same PE: a local memory on the link, the same
// counters, and its finished event at the same simulated time.
#pragma once

#include "machine/engine_driver.h"
#include "machine/pe.h"
#include "engine/pe_engine.h"

namespace rtm {

class EnginePe : public Pe {
 public:
  SC_HAS_PROCESS(EnginePe);
  EnginePe(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units,
           size_t pixels, Timekeeper* keeper, EngineDriver& driver);

  bool finished() const override { return finished_; }
  FifoStatsList fifo_stats() override;
  std::string occupancy_report() override;
  void trace(Waveform& wave) override;

  /// The engine runs at most two of these ahead of SystemC time, so that the progress display
  /// and the stall watch (watchdog.h) keep seeing the PE's counters move. Each quantum visits
  /// every PE whose rays are in, and by then that PE's state is out of the processor's caches:
  /// at 256 PEs a shorter quantum costs more in those visits than in the simulation.
  static constexpr uint64_t kQuantumCycles = 65536;

 private:
  void run();

  PeEngine engine_;
  EngineDriver& driver_;
  bool finished_ = false;
};

}  // namespace rtm
