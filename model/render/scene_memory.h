// The scene as a PE's local memory holds it, in the machine's precision: what the MAC, the root
// unit and the clip tests read.
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

  MacNumerics numerics;  ///< discriminant form and coefficient scaling (geom/numerics.h)

  SceneMemory(const Scene& s, const Grid& g, bool recentre = true, MacNumerics num = {})
      : scene(&s), grid(&g), numerics(num) {
    rams.reserve(s.primitives.size());
    for (const Primitive& p : s.primitives) {
      Vec3 c{0, 0, 0};
      if (recentre) {
        // The machine latch subtracts the stored centre from the origin rounded to Real, so the
        // centre must be a Real; the wide latches subtract in fp64 and keep the box centre itself,
        // or the shape's own origin where its local form has no linear terms (a sphere's centre:
        // its box's centre rounds differently once the host has moved it into the grid's frame),
        // so a centred shape has none, and sparse MAC schedules skip them.
        const bool centred =
            p.has_local && p.local.c[kG] == 0 && p.local.c[kH] == 0 && p.local.c[kI] == 0;
        const Vec3 mid = centred && num.origin != OriginLatch::Machine
                             ? p.origin
                             : 0.5 * (p.bounds.lo + p.bounds.hi);
        c = num.origin == OriginLatch::Machine
                ? Vec3(round_to_real<Real>(mid.x), round_to_real<Real>(mid.y),
                       round_to_real<Real>(mid.z))
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
  double t_shift(double t_enter) const {
    return numerics.origin == OriginLatch::Advance ? t_enter : 0.0;
  }

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

}  // namespace rtm
