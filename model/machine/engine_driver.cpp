#include "machine/engine_driver.h"

#include <algorithm>
#include <thread>

namespace rtm {

int engine_threads(int sim_threads, int pes) {
  const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(1, std::min(sim_threads > 0 ? sim_threads : cores, pes));
}

EngineDriver::EngineDriver(sc_core::sc_module_name name, WorkerPool& pool)
    : sc_module(name), pool_(pool) {
  SC_THREAD(drive);
}

void EngineDriver::run_before(PeEngine& engine, uint64_t t) {
  bool done = false;
  asked_.push_back({&engine, t, &done});
  // The PEs woken at this instant all ask within one delta cycle; the batch runs in the next.
  asked_event_.notify(sc_core::SC_ZERO_TIME);
  // One asking after this delta's batch has run waits for the next one.
  while (!done) sc_core::wait(ran_event_);
}

void EngineDriver::drive() {
  for (;;) {
    sc_core::wait(asked_event_);
    const std::vector<Request> batch = std::move(asked_);
    asked_.clear();
    pool_.run(batch.size(), [&](size_t i) { batch[i].engine->run_before(batch[i].t); });
    for (const Request& r : batch) *r.done = true;
    ran_event_.notify(sc_core::SC_ZERO_TIME);
  }
}

}  // namespace rtm
