#include "machine/engine_pe.h"

#include <algorithm>

namespace rtm {

EnginePe::EnginePe(sc_core::sc_module_name name, int index, const MachineConfig& c,
                   const PeUnits& units, size_t pixels, Timekeeper* keeper, EngineDriver& driver)
    : Pe(name, index, c, units, pixels, keeper),
      engine_(ctx, memory.frame, memory.ids, memory.rays, memory.rays_expected),
      driver_(driver) {
  SC_THREAD(run);
}

void EnginePe::run() {
  // Only the host's rays reach a PE from outside, and they land in local memory: while some may
  // still come the engine keeps behind SystemC time; otherwise it runs one to two quanta ahead, on
  // quantum boundaries shared by every PE, so that the driver runs the PEs side by side. A
  // dynamic partition's rays come only as answers to the PE's requests for tiles (the first
  // unasked): between an answer and its next request nothing can reach it, so it runs ahead until
  // it asks, then asks at the time it did. A run of several frames is alike: the next frame's rays
  // are taken only once the frame the PE is on has ended, so it runs ahead once that frame's rays
  // are in, until the frame ends, and tells the host then.
  const uint64_t quantum = ctx.period.value() * kQuantumCycles;
  const bool dynamic = ctx.config.partition == Partition::Dynamic;
  size_t expected = memory.rays_expected, answers_due = 1;
  auto rays_for_now = [&] {
    return ctx.frame_rays ? std::min(expected, (memory.frames_ended() + 1) * size_t(ctx.frame_rays))
                          : expected;
  };
  for (bool all_in = false;;) {
    const uint64_t now = sc_core::sc_time_stamp().value();
    if (!all_in) {
      engine_.run_before(now);
      if (memory.rays.size() > engine_.rays_known() || memory.rays_expected != expected) {
        expected = memory.rays_expected;
        engine_.rays_arrived(now, memory.rays.size(), expected);
      }
      all_in = dynamic ? memory.transfers_in == answers_due : memory.rays.size() >= rays_for_now();
    }
    const uint64_t boundary = (now / quantum + 1) * quantum;
    if (all_in) driver_.run_before(engine_, boundary + quantum);
    if (const uint64_t asked = engine_.take_ask(); asked != PeEngine::kNever) {
      if (asked > now) sc_core::wait(sc_core::sc_time::from_value(asked - now));
      memory.ask_for_tile();
      ++answers_due;
      all_in = false;
      continue;
    }
    if (const uint64_t ended = engine_.take_frame_end(); ended != PeEngine::kNever) {
      if (ended > now) sc_core::wait(sc_core::sc_time::from_value(ended - now));
      memory.frame_ended();
      all_in = false;
      continue;
    }
    if (engine_.finished()) break;
    if (all_in && engine_.idle())
      return;  // rays outstanding and nothing to do: the machine reports it
    if (all_in)
      sc_core::wait(sc_core::sc_time::from_value(boundary - now));
    else
      sc_core::wait(sc_core::sc_time::from_value(quantum), memory.rays_arrived);
  }
  const sc_core::sc_time at = sc_core::sc_time::from_value(engine_.finish_time());
  if (at > sc_core::sc_time_stamp()) sc_core::wait(at - sc_core::sc_time_stamp());
  sc_core::wait(sc_core::SC_ZERO_TIME);  // the modules' front buffer sees the last end a delta late
  finished_ = true;
  finished_event.notify(sc_core::SC_ZERO_TIME);
}

FifoStatsList EnginePe::fifo_stats() {
  return engine_.fifo_stats(sc_core::sc_time_stamp().value(),
                            sc_core::sc_get_time_resolution().to_seconds());
}

std::string EnginePe::occupancy_report() {
  return std::string(name()) + ": " + engine_.occupancy_report();
}

void EnginePe::trace(Waveform&) {
  SC_REPORT_ERROR("rtm/pe",
                  "a PE on the engine has no signals to trace (waveforms select the modules)");
}

}  // namespace rtm
