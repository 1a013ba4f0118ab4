// Where a unit's finished work goes: the FIFO (units/fifo_table.h) and what is written there.
// The unit decides it once; each scheduler only writes it.
#pragma once

#include "units/fifo_table.h"
#include "units/machine_ray.h"
#include "units/pe_state.h"

namespace rtm {

struct Output {
  FifoId fifo = FifoId::Ends;
  /// Item: the ray (or MAC result) the unit worked on, or one it made (shading's spawned rays);
  /// End: the end of the ray it worked on (RayEnd), which returns the ray's credit.
  enum class What : uint8_t { Item, End } what = What::End;
};

/// A unit's work on one item: its cycles, where its result goes, and what it asked of local
/// memory. Every unit's take() gets the time it is taken at (ticks) for the event log and for
/// its memory requests.
struct Work {
  uint64_t cycles = 0;    ///< latency: from taking the item to its result
  uint64_t interval = 0;  ///< until the unit can take its next item (units/pipeline.h)
  Output out;
  MemoryWait wait;  ///< its local-memory requests (units/pe_memory.h): the scheduler hands them to
                    ///< its pipeline
};

/// A unit's interval for an item of `latency` cycles that passes its first stage `beats` times:
/// `key` cycles a beat, or, with key 0 (unpipelined), the item's whole latency.
inline uint64_t pipeline_interval(int key, uint64_t latency, uint64_t beats = 1) {
  return key > 0 ? uint64_t(key) * beats : latency;
}

/// Records that unit (kind, index) wrote `out` for ray `ray` at `now`: every scheduler calls it
/// after each write, so their event logs, and the times the pixels are done, agree.
inline void record_put(PeState& pe, uint64_t now, UnitKind kind, int index, const MachineRay& ray,
                       const Output& out) {
  if (out.what == Output::What::End) pe.ray_ended(ray.slot, now);
  if (pe.log) pe.log->put(now, kind, index, ray.id, out.fifo);
}

/// The front buffer's next primary ray (pixel slot `slot`), numbered and counted.
inline MachineRay primary_ray(PeState& pe, const std::vector<Ray>& rays, size_t slot) {
  MachineRay m;
  m.ray = rays[slot];
  m.slot = uint32_t(slot);
  m.id = pe.next_ray_id++;
  ++pe.counters.counts.rays[size_t(RayKind::Primary)];
  pe.rays_made(m.slot, 1);
  return m;
}

}  // namespace rtm
