#include "machine/unit_work.h"

#include <algorithm>

namespace rtm {

Routed search_work(PeContext& ctx, MachineRay& r) {
  const MachineConfig& c = ctx.config;
  const Grid& g = *ctx.image->grid;
  const bool walk_on = c.search_walk == MachineConfig::SearchWalk::UntilOccupied;
  uint64_t cycles = 0;
  Route route;
  for (;;) {
    const bool examined = search_pass(g, r);
    route = search_route(*ctx.image->scene, g, r, examined);
    // Reading the voxel entry only happens when there is a voxel to examine.
    cycles += uint64_t(c.dda_step_cycles) + (examined ? uint64_t(c.voxel_read_cycles) : 0);
    if (examined) ++ctx.counters.counts.voxel_steps;
    if (!(walk_on && route == Route::Feedback)) break;
  }
  ctx.counters.search.busy_cycles += cycles;
  ++ctx.counters.search.items;
  return {route, cycles};
}

uint64_t mac_work(PeContext& ctx, const MacTiming& timing, MacResult& m) {
  const SceneImage& img = *ctx.image;
  const DdaState& s = m.r.examined;
  const int64_t v = img.grid->index(s.cell[0], s.cell[1], s.cell[2]);
  const int n = int(img.grid->count(v));
  const bool fp32 = ctx.config.precision == Precision::Fp32;
  if (fp32)
    form_voxel_abg(img.mem32, m.r.ray, v, m.abg32, s.t_enter);
  else
    form_voxel_abg(img.mem64, m.r.ray, v, m.abg64, s.t_enter);
  std::vector<int>& counts = m.plan.counts;  // filled in place: a MacResult is reused
  counts.clear();
  int products = 0;
  for (const uint32_t *it = img.grid->begin(v), *end = it + n; it != end; ++it) {
    counts.push_back(fp32 ? img.mem32.products(*it) : img.mem64.products(*it));
    products += counts.back();
  }
  timing.plan(m.plan);
  const uint64_t cycles = m.plan.cycles();
  ctx.counters.mac_products += uint64_t(products);
  ctx.counters.mac_products_saved += uint64_t(n) * kMacProducts - uint64_t(products);
  ctx.counters.mac_cycles_saved += timing.job_cycles(n) - cycles;
  ctx.counters.mac.busy_cycles += cycles;
  ++ctx.counters.mac.items;
  return cycles;
}

uint64_t back_end_cycles(const MachineConfig& c, const MacTiming::Job& mac, const std::vector<uint32_t>& clips) {
  uint64_t unit_free = 0;
  for (size_t p = 0; p < clips.size(); ++p) {
    const uint64_t ready = mac.done(int(p)) + 1 + uint64_t(c.root_cycles());
    unit_free = std::max(unit_free, ready) + clips[p] * uint64_t(c.clip_cycles) + uint64_t(c.sort_cycles);
  }
  return unit_free - mac.cycles();
}

Routed root_work(PeContext& ctx, MacResult& m, std::vector<uint32_t>& clips) {
  MachineRay& r = m.r;
  const SceneImage& img = *ctx.image;
  const int64_t v = img.grid->index(r.examined.cell[0], r.examined.cell[1], r.examined.cell[2]);
  const VoxelHit h = ctx.config.precision == Precision::Fp32
                         ? resolve_voxel(img.mem32, r.ray, r.examined, v, m.abg32.data(), &clips)
                         : resolve_voxel(img.mem64, r.ray, r.examined, v, m.abg64.data(), &clips);
  ctx.counters.counts.intersection_tests += h.tests;
  ctx.counters.counts.clip_tests += h.clip_tests;
  const uint64_t cycles = back_end_cycles(ctx.config, m.plan, clips);
  ctx.counters.root.busy_cycles += cycles;
  ++ctx.counters.root.items;
  return {intersection_route(*img.scene, r, h), cycles};
}

uint64_t shade_work(PeContext& ctx, const MachineRay& r, PixelSum& pixel, int32_t& primary_id, ShadeOut& out) {
  const MachineConfig& c = ctx.config;
  const Scene& s = *ctx.image->scene;
  out.rays.clear();
  uint64_t cycles = 0;
  switch (r.arrival) {
    case MachineRay::Arrival::Hit:
      if (r.ray.kind == RayKind::Primary) primary_id = int32_t(r.prim);
      shade_hit(s, r.ray, r.t_hit, s.primitives[r.prim], out);
      pixel.add(out.brightness);
      cycles = uint64_t(c.shade_cycles) + uint64_t(c.spawn_cycles) * out.rays.size();
      break;
    case MachineRay::Arrival::LightReached:
      pixel.add(r.ray.brightness);
      cycles = uint64_t(c.accumulate_cycles);
      break;
    case MachineRay::Arrival::Missed:
      pixel.add(miss_brightness(s, r.ray));
      cycles = uint64_t(c.accumulate_cycles);
      break;
  }
  ctx.counters.shade.busy_cycles += cycles;
  ++ctx.counters.shade.items;
  return cycles;
}

}  // namespace rtm
