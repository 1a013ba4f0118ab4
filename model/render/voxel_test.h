// Testing one voxel: the intersection stage's arithmetic (the MAC's α, β, γ, the roots, clips
// and the nearest hit), shared by the reference renderer (which runs a walk to completion) and
// the machine (one voxel per pass).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "geom/dda.h"
#include "render/scene_memory.h"

namespace rtm {

struct VoxelHit {
  bool hit = false;
  double t = kInf;
  uint32_t prim = 0;
  uint32_t tests = 0;       ///< primitives tested (each one pass of the MAC schedule)
  uint32_t clip_tests = 0;  ///< half-space evaluations
};

/// How far back, as a fraction of the voxel's window, a voxel entered with the advanced origin
/// latch accepts a hit: float rounding of a root measured from the voxel's entry is about 1e-7 of
/// the distances the latches hold, which a grid of up to ~1000 voxels a side keeps below this.
constexpr double kAdvancedWindowReach = 1e-4;

/// How far before the voxel's t_enter a hit still counts in it. The walk's t_enter is rounded and
/// may lie past the true entry (by at most DdaState::t_enter_slack): a hit just past the entry
/// face would fall before it, and the voxel before need not list its primitive. Measured from
/// each voxel's own entry point (the advanced latch), a hit on the face between two voxels is
/// also rounded differently in each: that window reaches back a fraction of itself too. Either
/// only finds what the voxel before rounded out, and never reaches behind the ray's start. The
/// paper's latch keeps the walk's windows as they are.
inline double entry_reach(OriginLatch latch, const DdaState& s, double t_hi) {
  if (latch == OriginLatch::Machine) return 0.0;
  double reach = s.t_enter_slack;
  if (latch == OriginLatch::Advance)
    reach = std::max(reach, kAdvancedWindowReach * (t_hi - s.t_enter));
  return std::min(reach, s.t_enter);
}

/// The window of the current voxel in which a hit counts: shadow rays also stop at their light.
inline double window_end(const Ray& r, const DdaState& s) { return std::min(s.t_exit, r.t_max); }

/// The MAC's job for one voxel: α, β, γ for every primitive the voxel lists, in list order.
/// t_enter: where the ray enters the voxel (DdaState::t_enter; used by OriginLatch::Advance).
template <class Real>
void form_voxel_abg(const SceneMemory<Real>& mem, const Ray& ray, int64_t voxel,
                    std::vector<Abg<Real>>& out, double t_enter = 0) {
  const Grid& g = *mem.grid;
  out.clear();
  for (const uint32_t *it = g.begin(voxel), *end = it + g.count(voxel); it != end; ++it)
    out.push_back(form_abg(mem.latches(ray, *it, t_enter), mem.rams[*it],
                           mem.masks.empty() ? kAllProducts : mem.masks[*it]));
}

/// The root unit and the sort for one voxel: roots of each primitive's α t² + β t + γ, clip
/// tests, and the nearest hit inside the voxel (ties go to the lower primitive number, the order
/// the voxel lists them in). Every listed primitive is tested, as the paper's §5.1 says.
/// `clips_per_prim`, if given, receives each primitive's clip-test count (for the machine's
/// timing).
template <class Real>
VoxelHit resolve_voxel(const SceneMemory<Real>& mem, const Ray& ray, const DdaState& s,
                       int64_t voxel, const Abg<Real>* abg,
                       std::vector<uint32_t>* clips_per_prim = nullptr) {
  VoxelHit best;
  const Grid& g = *mem.grid;
  const double t_hi = window_end(ray, s);
  const double shift = mem.t_shift(s.t_enter);  // roots are measured from V + shift·U
  const double reach_back = entry_reach(mem.numerics.origin, s, t_hi);
  const uint32_t* ids = g.begin(voxel);
  if (clips_per_prim) clips_per_prim->clear();
  for (uint32_t i = 0, n = g.count(voxel); i < n; ++i) {
    const Abg<Real>& c = abg[i];
    PrimitiveHit h = first_hit_in_window(
        mem.clips[ids[i]], solve_quadratic(c.a, c.b, c.g, mem.numerics.discriminant),
        mem.latches(ray, ids[i], s.t_enter), -shift, s.t_enter - shift - reach_back, t_hi - shift);
    if (h.hit) h.t += shift;
    ++best.tests;
    best.clip_tests += uint32_t(h.clip_tests);
    if (clips_per_prim) clips_per_prim->push_back(uint32_t(h.clip_tests));
    if (h.hit && h.t < best.t) {
      best.hit = true;
      best.t = h.t;
      best.prim = ids[i];
    }
  }
  return best;
}

}  // namespace rtm
