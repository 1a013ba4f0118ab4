// The front buffer at the head of the PE's macro-pipeline (paper §4.2): it merges the host's
// primary rays with the rays fed back by the stages and hands them to the search units.
//
// Arbitration: rays already in the loop (fed back or spawned) go first, in arrival order; a new
// primary ray is admitted only when none is waiting. Flow control: a ray past the front buffer
// holds one of `credits` credits until it comes back or ends, and every FIFO past the front
// buffer is at least `credits` deep, so no stage ever waits on a full FIFO downstream; the
// front buffer itself never refuses a ray (beyond its on-chip capacity rays spill to local
// memory), so the feedback paths always drain. Hence no cycle of waits can form: no deadlock.
#pragma once

#include <deque>

#include <systemc>

#include "machine/local_memory.h"
#include "machine/machine_ray.h"
#include "machine/metered_fifo.h"

namespace rtm {

class FrontBuffer : public sc_core::sc_module {
 public:
  sc_core::sc_fifo_in<MachineRay> from_search{"from_search"};       ///< empty voxel: walk on
  sc_core::sc_fifo_in<MachineRay> from_intersect{"from_intersect"}; ///< no hit in the voxel: walk on
  /// Spawned shadow and branch rays; left unbound when the scene spawns none.
  sc_core::sc_port<sc_core::sc_fifo_in_if<MachineRay>, 1, sc_core::SC_ZERO_OR_MORE_BOUND> from_shade{"from_shade"};
  sc_core::sc_fifo_in<RayEnd> ends_in{"ends_in"};                   ///< rays that left the loop
  sc_core::sc_fifo_out<MachineRay> rays_out{"rays_out"};            ///< to the search units

  SC_HAS_PROCESS(FrontBuffer);
  /// `finished` is notified when every ray of the PE's part of the frame has ended.
  FrontBuffer(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem, sc_core::sc_event& finished);

  bool finished() const { return finished_; }
  /// Rays past the front buffer and rays waiting in it, for deadlock reports.
  int in_flight() const { return in_flight_; }
  size_t waiting() const { return queue_.size(); }
  void trace(sc_core::sc_trace_file* tf, const std::string& prefix);

 private:
  void run();
  void drain();
  /// Hands a ray to the search units, taking `cycles`.
  void dispatch(MachineRay r, uint64_t cycles);

  PeContext& ctx_;
  std::unique_ptr<Sleeper> sleep_;
  LocalMemory& mem_;
  int credits_;
  std::deque<MachineRay> queue_;
  size_t next_primary_ = 0;
  int in_flight_ = 0;
  bool finished_ = false;
  sc_core::sc_event& finished_event_;
  UnitProbe probe_;
  int traced_waiting_ = 0;
  sc_core::sc_event_or_list inputs_;  ///< any input FIFO written, or primary rays arrived
};

}  // namespace rtm
