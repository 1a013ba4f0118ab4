#include "units/intersection.h"

#include <algorithm>

namespace rtm {

Work MacUnit::take(MacResult& m, uint64_t now) {
  const SceneImage& img = *pe_.image;
  const DdaState& s = m.r.examined;
  const int64_t v = img.grid->index(s.cell[0], s.cell[1], s.cell[2]);
  const int n = int(img.grid->count(v));
  std::vector<int>& counts = m.plan.counts;  // filled in place: a MacResult is reused
  std::vector<uint64_t>& loads = m.plan.loads;
  counts.clear();
  loads.clear();
  int products = 0;
  PeMemory* mem = pe_.memory.get();
  auto form = [&](const auto& sm, auto& abg) {
    form_voxel_abg(sm, m.r.ray, v, abg, s.t_enter);
    for (const uint32_t *it = img.grid->begin(v), *end = it + n; it != end; ++it) {
      counts.push_back(sm.products(*it));
      products += counts.back();
      // A primitive's coefficients not in the MAC's RAM are loaded from local memory first.
      if (mem)
        loads.push_back(mem->coef_ram(lane_).access(*it) ? 0 : mem->unloaded(mem->coef_bytes(*it)));
    }
  };
  if (img.mem32)
    form(*img.mem32, m.abg32);
  else
    form(*img.mem64, m.abg64);
  timing_.plan(m.plan);
  Work w;
  w.cycles = m.plan.cycles();
  if (mem && n > 0) {
    // The voxel's list within the job; each miss's record before its primitive's first product.
    const uint64_t cycle = now / pe_.cycle, who = uint64_t(mem->lane(lane_));
    w.wait.latency = w.cycles;
    const PeMemory::VoxelRead list = mem->voxel_read(
        mem->addresses().voxel_list(img.grid->start[size_t(v)]), voxel_list_bytes(uint64_t(n)));
    if (list.bytes)
      mem->request(int(who), list.address, list.bytes, cycle, std::max(w.cycles, list.cycles),
                   w.wait);
    const uint32_t* prims = img.grid->begin(v);
    for (int p = 0; p < n; ++p)
      if (loads[size_t(p)] > 0)
        mem->request(int(who), mem->addresses().coef_record(prims[p]), mem->coef_bytes(prims[p]),
                     cycle, m.plan.start[size_t(p)], w.wait);
  }
  // Streaming, the next job's first coefficients load while this job's last primitive issues.
  w.interval = pe_.config.mac_streaming ? m.plan.issue_span() : w.cycles;
  w.out = {FifoId::Root, Output::What::Item};
  PeCounters& k = pe_.counters;
  k.mac_products += uint64_t(products);
  k.mac_products_saved += uint64_t(n) * kMacProducts - uint64_t(products);
  // What the same job takes of the MAC's entry under the full schedule, with the same loads
  // (MacTiming::plan's rule for 28 products a primitive, without building the plan).
  const uint64_t slot = uint64_t(kMacProducts) * uint64_t(timing_.add_latency);
  uint64_t full = 0;
  if (n > 0) {
    uint64_t at = loads.empty() ? 0 : loads[0];
    for (int p = 0; p < n; ++p)
      at += std::max<uint64_t>(slot, size_t(p + 1) < loads.size() ? loads[size_t(p + 1)] : 0);
    // Streaming: its issue slots; else its last sums out (the last primitive's slot less its
    // last product's add, plus the pipe) and one cycle.
    full = pe_.config.mac_streaming
               ? at
               : at - uint64_t(timing_.add_latency) + uint64_t(m.plan.pipe) + 1;
  }
  k.mac_cycles_saved += full - w.interval;
  if (pe_.log) pe_.log->take(now, UnitKind::Mac, lane_, m.r.id, w.cycles);
  return w;
}

uint64_t back_end_cycles(const MachineConfig& c, const MacTiming::Job& mac,
                         const std::vector<uint32_t>& clips) {
  uint64_t unit_free = 0;
  for (size_t p = 0; p < clips.size(); ++p) {
    const uint64_t ready = mac.done(int(p)) + 1 + uint64_t(c.root_cycles());
    unit_free =
        std::max(unit_free, ready) + clips[p] * uint64_t(c.clip_cycles) + uint64_t(c.sort_cycles);
  }
  return unit_free - mac.cycles();
}

Work RootUnit::take(MacResult& m, uint64_t now) {
  MachineRay& r = m.r;
  const SceneImage& img = *pe_.image;
  const int64_t v = img.grid->index(r.examined.cell[0], r.examined.cell[1], r.examined.cell[2]);
  const VoxelHit h = img.mem32
                         ? resolve_voxel(*img.mem32, r.ray, r.examined, v, m.abg32.data(), &clips_)
                         : resolve_voxel(*img.mem64, r.ray, r.examined, v, m.abg64.data(), &clips_);
  pe_.counters.counts.intersection_tests += h.tests;
  pe_.counters.counts.clip_tests += h.clip_tests;
  Work w;
  w.cycles = back_end_cycles(pe_.config, m.plan, clips_);
  w.interval = pipeline_interval(pe_.config.root_interval, w.cycles, clips_.size());
  switch (intersection_route(*img.scene, r, h)) {
    case Route::Shade:
      w.out = {FifoId::Shade, Output::What::Item};
      break;
    case Route::Feedback:
      w.out = {FifoId::FeedbackIntersect, Output::What::Item};
      break;
    case Route::End:
      w.out = {FifoId::Ends, Output::What::End};
      break;
    case Route::Intersect:
      break;  // not a route out of this unit
  }
  if (pe_.log) pe_.log->take(now, UnitKind::Root, lane_, r.id, w.cycles);
  return w;
}

}  // namespace rtm
