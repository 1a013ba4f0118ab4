// The whole machine: the host, N PEs and the link between them, run for one frame.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/worker_pool.h"
#include "frame/machine_result.h"
#include "machine/host.h"

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
