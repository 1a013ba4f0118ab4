// Tracing one ray through the grid: the search and intersection stages' arithmetic, shared by
// the reference renderer (which runs it to completion) and the machine (one voxel per pass).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geom/dda.h"
#include "geom/intersect.h"
#include "render/ray.h"
#include "scene/scene.h"

namespace rtm {

/// Scene data as a PE's local memory holds it: primitives, their coefficient RAM images, voxels.
template <class Real>
struct SceneMemory {
  const Scene* scene = nullptr;
  const Grid* grid = nullptr;
  std::vector<CoefRam<Real>> rams;  ///< one coefficient RAM image per primitive

  SceneMemory(const Scene& s, const Grid& g) : scene(&s), grid(&g) {
    rams.reserve(s.primitives.size());
    for (const Primitive& p : s.primitives) rams.push_back(load_ram<Real>(p.q));
  }
};

struct VoxelHit {
  bool hit = false;
  double t = kInf;
  uint32_t prim = 0;
  uint32_t tests = 0;       ///< primitives tested (each one pass of the MAC schedule)
  uint32_t clip_tests = 0;  ///< half-space evaluations
};

/// The window of the current voxel in which a hit counts: shadow rays also stop at their light.
inline double window_end(const Ray& r, const DdaState& s) { return std::min(s.t_exit, r.t_max); }

/// The MAC's job for one voxel: α, β, γ for every primitive the voxel lists, in list order.
template <class Real>
void form_voxel_abg(const SceneMemory<Real>& mem, const Ray& ray, int64_t voxel, std::vector<Abg<Real>>& out) {
  const Grid& g = *mem.grid;
  const Latches<Real> latches = load_latches<Real>(ray.dir, ray.origin);
  out.clear();
  for (const uint32_t *it = g.begin(voxel), *end = it + g.count(voxel); it != end; ++it)
    out.push_back(form_abg(latches, mem.rams[*it]));
}

/// The root unit and the sort for one voxel: roots of each primitive's α t² + β t + γ, clip
/// tests, and the nearest hit inside the voxel (ties go to the lower primitive number, the order
/// the voxel lists them in). Every listed primitive is tested, as the paper's §5.1 says.
/// `clips_per_prim`, if given, receives each primitive's clip-test count (for the machine's timing).
template <class Real>
VoxelHit resolve_voxel(const SceneMemory<Real>& mem, const Ray& ray, const DdaState& s, int64_t voxel,
                       const Abg<Real>* abg, std::vector<uint32_t>* clips_per_prim = nullptr) {
  VoxelHit best;
  const Grid& g = *mem.grid;
  const Latches<Real> latches = load_latches<Real>(ray.dir, ray.origin);
  const double t_hi = window_end(ray, s);
  const uint32_t* ids = g.begin(voxel);
  if (clips_per_prim) clips_per_prim->clear();
  for (uint32_t i = 0, n = g.count(voxel); i < n; ++i) {
    const Abg<Real>& c = abg[i];
    const PrimitiveHit h =
        first_hit_in_window(mem.scene->primitives[ids[i]], solve_quadratic(c.a, c.b, c.g), latches, 0.0, s.t_enter, t_hi);
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

/// Both halves for the current voxel of a walk: what the intersection stage computes.
template <class Real>
VoxelHit intersect_voxel(const SceneMemory<Real>& mem, const Ray& ray, const DdaState& s,
                         std::vector<Abg<Real>>& scratch) {
  const int64_t v = mem.grid->index(s.cell[0], s.cell[1], s.cell[2]);
  form_voxel_abg(mem, ray, v, scratch);
  return resolve_voxel(mem, ray, s, v, scratch.data());
}

}  // namespace rtm
