// The whole machine: the host, N PEs and the link between them, run for one frame.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "machine/frame_stats.h"
#include "machine/host.h"
#include "engine/worker_pool.h"
#include "memory/memory_layout.h"
#include "units/fifo_table.h"
#include "units/pe_memory.h"
#include "render/scene_needs.h"

namespace rtm {

struct MachineOptions {
  std::string vcd;   ///< waveform file; empty: none
  std::string gtkw;  ///< GTKWave save file for it, naming every signal traced; empty: none
  uint64_t vcd_from_cycle = 0;  ///< waveform window, in PE cycles
  uint64_t vcd_to_cycle = UINT64_MAX;
  int vcd_anchor_pe = -1;       ///< >= 0: the window counts from this PE's first primary ray
  std::vector<int> vcd_pes{0};  ///< PEs whose signals are traced
  bool progress = false;        ///< one-line progress display on stderr
  std::string event_log;  ///< every unit event, one line each (units/event_log.h); empty: none
  /// The memory budget: the simulation stops with an error once the process holds more (what
  /// grows with the ray tree cannot be known before it runs). 0: none.
  uint64_t max_memory = 0;
  /// The work budget: the simulation stops with an error once its PEs have traced more rays. 0:
  /// none.
  uint64_t max_rays = 0;
  /// Threads that simulate the PEs on the engine side by side (machine/engine_driver.h); 0: one
  /// per core. The figures do not depend on it.
  int sim_threads = 0;
  /// Those threads started ahead (engine_threads() of them), or null: run_machine starts its own.
  /// rtm render starts them before the image library loads, since a thread started during the
  /// load waits for it to finish (0.27-0.30 s measured on balls-3).
  WorkerPool* pool = nullptr;
};

/// Per FIFO kind, over all PEs.
struct FifoSummary {
  std::string kind;
  int depth = 0;
  int peak = 0;
  double mean = 0;  ///< time-weighted mean occupancy, averaged over the FIFOs of this kind
};

struct MachineResult {
  Image image;
  TraceCounts counts;
  uint64_t mac_products = 0, mac_busy_cycles = 0, mac_issue_cycles = 0, spills = 0;
  std::vector<PeCounters> per_pe;
  std::vector<FifoSummary> fifos;
  std::array<uint64_t, kFifoCount>
      fifo_writes{};  ///< records written into each FIFO of the table, over all PEs
  HostTimes host;
  std::vector<LinkUse>
      links;  ///< the interconnect's links: busy time and bytes of each (net/interconnect.h)
  uint64_t scene_bytes = 0;           ///< one PE's copy of the scene as the link carries it
  std::vector<MemoryLayout> memory;   ///< each PE's local memory (memory/memory_layout.h)
  std::vector<MemoryUse> memory_use;  ///< what each PE's local memory did (units/pe_memory.h)
  sc_core::sc_time end;
  uint64_t cycles = 0;  ///< the frame's simulated time in PE cycles
  FrameStats stats;     ///< derived from the counters above (frame_stats.h)
  double wall_seconds = 0;
  SceneNeeds needs;                         ///< what the scene can use (render/scene_needs.h)
  std::vector<std::string> left_out_units;  ///< per PE, not elaborated
  uint64_t mac_products_saved = 0,
           mac_cycles_saved = 0;   ///< by sparse MAC schedules (cycles: of the MAC's entry)
  PeUnits units;                   ///< what each PE elaborated
  std::string engine_unsupported;  ///< why the PEs ran as modules; empty: on the PE engine
  std::vector<std::string>
      warnings;  ///< for the user, one line each (e.g. a waveform window that recorded nothing)
  bool deadlock = false;
  std::string deadlock_report;  ///< every FIFO's occupancy when the simulation stalled
};

/// A valid configuration that is more than this host can run (rtm exits 2, as for a bad
/// configuration): e.g. more SystemC threads than the process may map stacks for.
struct MachineLimitError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Elaborates and simulates the machine. SystemC elaborates once per process: call it once.
MachineResult run_machine(const Scene& s, const Grid& g, const MachineConfig& c,
                          const MachineOptions& opt);

/// The file a waveform option names: SystemC's trace files end in ".vcd", added if missing.
std::string vcd_file(const std::string& vcd);

}  // namespace rtm
