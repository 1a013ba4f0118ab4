// What each unit of a PE does with one item and how many cycles it takes, apart from when it
// does it: the SystemC modules (front_buffer.h … shading_stage.h) and the PE engine
// (pe_engine.h) schedule the same work, so they cannot disagree on a value or a cycle count.
#pragma once

#include <cstdint>
#include <vector>

#include "machine/mac.h"
#include "machine/machine_ray.h"
#include "machine/pe_context.h"
#include "machine/routing.h"
#include "render/pixel_sum.h"
#include "render/shade.h"

namespace rtm {

/// Where a unit sends its item, and the cycles it took.
struct Routed {
  Route route;
  uint64_t cycles;
};

/// A search unit's pass (or passes, with search_walk = until_occupied) over `r`.
Routed search_work(PeContext& ctx, MachineRay& r);

/// What the MAC hands the root unit: the ray and α, β, γ per primitive of its voxel.
struct MacResult {
  MachineRay r;
  MacTiming::Job plan;  ///< when each primitive's sums left the MAC
  std::vector<Abg<float>> abg32;
  std::vector<Abg<double>> abg64;
};
inline std::ostream& operator<<(std::ostream& os, const MacResult& m) { return os << m.r; }

/// The MAC's job for m.r's examined voxel: fills abg and plan, counts products; returns cycles.
uint64_t mac_work(PeContext& ctx, const MacTiming& timing, MacResult& m);

/// Cycles the root unit, clip tests and sort need after the MAC finished a voxel, given each
/// primitive's clip-test count: primitive p's roots are out root_latency after its sums, and its
/// clip tests and sort then run on one shared unit.
uint64_t back_end_cycles(const MachineConfig& c, const MacTiming::Job& mac, const std::vector<uint32_t>& clips);

/// The root unit and sort for a MAC result; routes m.r (§5.1). `clips`: scratch.
Routed root_work(PeContext& ctx, MacResult& m, std::vector<uint32_t>& clips);

/// Shading one ray into its pixel; `out` receives the rays to spawn. Returns cycles.
uint64_t shade_work(PeContext& ctx, const MachineRay& r, PixelSum& pixel, int32_t& primary_id, ShadeOut& out);

/// The front buffer's next primary ray (pixel slot `slot`), numbered and counted.
inline MachineRay primary_ray(PeContext& ctx, const std::vector<Ray>& rays, size_t slot) {
  MachineRay m;
  m.ray = rays[slot];
  m.slot = uint32_t(slot);
  m.id = ctx.next_ray_id++;
  ++ctx.counters.counts.rays[size_t(RayKind::Primary)];
  return m;
}

/// A ray shading spawned from `parent`, numbered and counted.
inline MachineRay spawned_ray(PeContext& ctx, const MachineRay& parent, const Ray& child) {
  MachineRay m;
  m.ray = child;
  m.slot = parent.slot;
  m.id = ctx.next_ray_id++;
  ++ctx.counters.counts.rays[size_t(child.kind)];
  return m;
}

/// Writes v to a FIFO (a port or a FIFO pointer), first waiting while it is full. In ranked order
/// a unit facing a full FIFO tries again every cycle, as a hardware handshake would, so who gets
/// a freed place follows the units' ranks; otherwise it waits for the kernel's read event.
template <class Fifo, class T>
void put(Fifo&& fifo, const T& v, const PeContext& ctx, Sleeper& sleep) {
  if (ctx.keeper)
    while (fifo->num_free() == 0) sleep(ctx.cycle);
  fifo->write(v);
}

/// Cycles the front buffer takes to hand out one ray.
inline uint64_t dispatch_cycles(const MachineConfig& c, bool spilled, bool primary) {
  const bool generate = primary && c.ray_generation == MachineConfig::RayGeneration::Pe;
  return uint64_t(c.fb_dispatch_cycles) + (spilled ? uint64_t(c.spill_cycles) : 0) +
         (generate ? uint64_t(c.pe_ray_cycles) : 0);
}

}  // namespace rtm
