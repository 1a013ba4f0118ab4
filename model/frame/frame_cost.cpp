#include "frame/frame_cost.h"

namespace rtm {

FrameActivity frame_activity(const MachineResult& m, const MachineConfig& c, uint64_t pixels) {
  FrameActivity a;
  a.pes = c.pes;
  // Several frames: a frame of the steady state, its time and its share of the run's work.
  a.seconds = m.frame_cycles() * c.clock_ns * 1e-9;
  a.pixels = pixels;
  a.rays = m.counts.total_rays();
  a.voxel_steps = m.counts.voxel_steps;
  a.intersection_tests = m.counts.intersection_tests;
  a.clip_tests = m.counts.clip_tests;
  a.mac_products = m.mac_products;
  for (const PeCounters& p : m.per_pe)
    for (const UnitSpec& u : unit_table()) a.items[size_t(u.kind)] += p.total(u.kind).items;
  a.fifo_writes = m.fifo_writes;
  for (const MemoryUse& u : m.memory_use) {
    for (const MemoryUse::Requester& q : u.requesters) a.memory_bytes += q.bytes;
    a.coef_ram_fills += u.coef_misses;
    a.cache_accesses += u.cache_hits + u.cache_misses;
    a.cache_line_fills += u.cache_line_fills;
  }
  for (const LinkUse& l : m.links) a.link_bytes += l.bytes;
  a.voxel_primitives = m.voxel_primitives;
  a.voxel_references = m.voxel_references;
  if (const uint64_t n = m.frame_done.size(); n > 1) {
    for (uint64_t* x : {&a.rays, &a.voxel_steps, &a.intersection_tests, &a.clip_tests,
                        &a.mac_products, &a.coef_ram_fills, &a.cache_accesses, &a.cache_line_fills,
                        &a.memory_bytes, &a.link_bytes, &a.voxel_primitives, &a.voxel_references})
      *x /= n;
    for (uint64_t& x : a.items) x /= n;
    for (uint64_t& x : a.fifo_writes) x /= n;
  }
  return a;
}

MachineCost frame_cost(const MachineResult& m, const MachineConfig& c, uint64_t pixels,
                       uint64_t primitives, const Technology& t) {
  return machine_cost(c, m.units, primitives, frame_activity(m, c, pixels), t);
}

}  // namespace rtm
