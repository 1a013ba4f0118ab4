// Tracing one ray through the grid: the search and intersection stages' arithmetic, shared by
// the reference renderer (which runs it to completion) and the machine (one voxel per pass).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geom/dda.h"
#include "geom/intersect.h"
#include "geom/numerics.h"
#include "render/ray.h"
#include "scene/scene.h"

namespace rtm {

/// Scene data as a PE's local memory holds it: primitives, their coefficient RAM images, voxels.
///
/// With `recentre`, each primitive's coefficients and clips are stored relative to its own
/// centre c (its box centre, rounded to Real so the machine can subtract it exactly as stored),
/// and the ray origin latch is loaded with V − c: t is unchanged, and the constant term no
/// longer cancels far from the origin. Without it, coefficients are in world coordinates as in
/// the paper. `numerics` (geom/numerics.h, docs/numerics.md) selects the root unit's discriminant,
/// the scaling of the RAM image and how V reaches the latches (rounded then re-centred, re-centred
/// in fp64 then rounded, or advanced to the voxel's entry point first).
template <class Real>
struct SceneMemory {
  const Scene* scene = nullptr;
  const Grid* grid = nullptr;
  std::vector<CoefRam<Real>> rams;            ///< one coefficient RAM image per primitive
  std::vector<Vec3> centres;                  ///< each primitive's frame origin (zero: world frame)
  std::vector<std::vector<HalfSpace>> clips;  ///< each primitive's clips, in its frame
  std::vector<MacOps> ops;                    ///< sparse MAC schedules; empty: the full schedule
  std::vector<MacMask> masks;                 ///< the same schedules as bit masks

  MacNumerics numerics;                       ///< discriminant form and coefficient scaling (geom/numerics.h)

  SceneMemory(const Scene& s, const Grid& g, bool recentre = true, MacNumerics num = {})
      : scene(&s), grid(&g), numerics(num) {
    rams.reserve(s.primitives.size());
    for (const Primitive& p : s.primitives) {
      Vec3 c{0, 0, 0};
      if (recentre) {
        // The machine latch subtracts the stored centre from the origin rounded to Real, so the
        // centre must be a Real; the wide latches subtract in fp64 and keep the box centre itself
        // (a sphere then has no linear terms, and sparse MAC schedules skip them).
        const Vec3 mid = 0.5 * (p.bounds.lo + p.bounds.hi);
        c = num.origin == OriginLatch::Machine
                ? Vec3(round_to_real<Real>(mid.x), round_to_real<Real>(mid.y), round_to_real<Real>(mid.z))
                : mid;
      }
      centres.push_back(c);
      const Quadric q = recentre ? p.about(c) : p.q;
      rams.push_back(load_ram<Real>(num.coef_scaling == CoefScaling::Pow2 ? scaled_pow2(q) : q));
      std::vector<HalfSpace> local;
      for (const HalfSpace& h : p.clips) local.push_back(recentre ? h.translated(c) : h);
      clips.push_back(std::move(local));
    }
  }

  /// Switches the MAC to each primitive's sparse schedule (products with a zero coefficient
  /// word skipped; same sums, see sparse_ops).
  void use_sparse_schedule() {
    ops.clear();
    masks.clear();
    for (const CoefRam<Real>& r : rams) {
      ops.push_back(sparse_ops(r));
      masks.push_back(sparse_mask(r));
    }
  }
  /// Products the MAC runs for primitive `prim`.
  int products(uint32_t prim) const { return ops.empty() ? kMacProducts : int(ops[prim].size()); }

  /// Where the roots are measured from for a voxel entered at t_enter: 0, or t_enter when the
  /// origin latch is advanced (the root unit adds it back).
  double t_shift(double t_enter) const { return numerics.origin == OriginLatch::Advance ? t_enter : 0.0; }

  /// The U/V latches for testing primitive `prim`: V in the primitive's frame (for a voxel entered
  /// at t_enter, which only OriginLatch::Advance uses).
  Latches<Real> latches(const Ray& r, uint32_t prim, double t_enter = 0) const {
    const Vec3& c = centres[prim];
    if (numerics.origin != OriginLatch::Machine) {
      const double shift = t_shift(t_enter);
      const Vec3 v = shift != 0 ? r.origin + shift * r.dir : r.origin;
      return load_latches<Real>(r.dir, v - c);
    }
    Latches<Real> l = load_latches<Real>(r.dir, r.origin);
    l[kVx] = l[kVx] - Real(c.x);
    l[kVy] = l[kVy] - Real(c.y);
    l[kVz] = l[kVz] - Real(c.z);
    return l;
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
/// t_enter: where the ray enters the voxel (DdaState::t_enter; used by OriginLatch::Advance).
template <class Real>
void form_voxel_abg(const SceneMemory<Real>& mem, const Ray& ray, int64_t voxel, std::vector<Abg<Real>>& out,
                    double t_enter = 0) {
  const Grid& g = *mem.grid;
  out.clear();
  for (const uint32_t *it = g.begin(voxel), *end = it + g.count(voxel); it != end; ++it)
    out.push_back(
        form_abg(mem.latches(ray, *it, t_enter), mem.rams[*it], mem.masks.empty() ? kAllProducts : mem.masks[*it]));
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
  const double t_hi = window_end(ray, s);
  const double shift = mem.t_shift(s.t_enter);  // roots are measured from V + shift·U
  const uint32_t* ids = g.begin(voxel);
  if (clips_per_prim) clips_per_prim->clear();
  for (uint32_t i = 0, n = g.count(voxel); i < n; ++i) {
    const Abg<Real>& c = abg[i];
    PrimitiveHit h = first_hit_in_window(mem.clips[ids[i]], solve_quadratic(c.a, c.b, c.g, mem.numerics.discriminant),
                                         mem.latches(ray, ids[i], s.t_enter), -shift, s.t_enter - shift, t_hi - shift);
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

/// Both halves for the current voxel of a walk: what the intersection stage computes.
template <class Real>
VoxelHit intersect_voxel(const SceneMemory<Real>& mem, const Ray& ray, const DdaState& s,
                         std::vector<Abg<Real>>& scratch) {
  const int64_t v = mem.grid->index(s.cell[0], s.cell[1], s.cell[2]);
  form_voxel_abg(mem, ray, v, scratch, s.t_enter);
  return resolve_voxel(mem, ray, s, v, scratch.data());
}

}  // namespace rtm
