// Runs the PE engines of one simulated instant side by side on a WorkerPool. Once a PE holds all
// its primary rays (of a dynamic partition: between the host's answer and the PE's next request)
// nothing from outside reaches it, so its engine may run ahead of SystemC time (engine_pe.cpp), and
// the engines of different PEs share no state: those asked to advance at the same instant run in
// parallel, each exactly as it would alone. Every figure is the same whatever the number of threads
// (tb/engine_test.cpp, EngineOnThreads).
#pragma once

#include <cstdint>
#include <vector>

#include <systemc>

#include "engine/pe_engine.h"
#include "engine/worker_pool.h"

namespace rtm {

/// The threads the PE engines of a machine of `pes` PEs run on: `sim_threads` (0: one per core),
/// but no more than the PEs (a thread beyond them would only wait).
int engine_threads(int sim_threads, int pes);

class EngineDriver : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(EngineDriver);
  /// `pool` must outlive the driver.
  EngineDriver(sc_core::sc_module_name name, WorkerPool& pool);

  /// From a PE's SystemC thread: simulates everything `engine` does before time t, together with
  /// the other engines asked to at this instant, and returns once it has.
  void run_before(PeEngine& engine, uint64_t t);

 private:
  void drive();

  struct Request {
    PeEngine* engine;
    uint64_t t;
    bool* done;
  };
  std::vector<Request> asked_;  ///< since the last batch
  sc_core::sc_event asked_event_, ran_event_;
  WorkerPool& pool_;
};

}  // namespace rtm
