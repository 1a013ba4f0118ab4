// Ray/primitive intersection as the machine does it: α, β, γ from the MAC schedule, the root
// unit, then the clip half-spaces. Templated on the arithmetic precision (float for the
// paper-like machine, double for the reference).
#pragma once

#include <cmath>
#include <cstdint>

#include "geom/mac_schedule.h"

namespace rtm {

template <class Real>
struct Roots {
  int n = 0;  ///< 0, 1 (linear case) or 2 (t0 <= t1; equal for a double root)
  Real t0 = 0, t1 = 0;
};

/// How the root unit forms the discriminant Δ = b² − 4ac (docs/numerics.md).
enum class Discriminant : uint8_t {
  Plain,  ///< b·b − (4a)·c, each product rounded: cancels near a double root (the paper-like unit)
  Fma,  ///< difference of products with fused multiply-adds (Kahan): Δ to about one ulp
};

/// b² − 4ac. Fma: w = (4a)·c rounded, e = w − (4a)·c exactly (an FMA), Δ = fma(b, b, −w) + e,
/// accurate to about 1.5 ulp of Δ whatever the cancellation (4a is exact). Needs a true fused
/// multiply-add (std::fma), never contraction by the compiler (the build disables it).
template <class Real>
Real discriminant(Real a, Real b, Real c, Discriminant mode) {
  if (mode == Discriminant::Plain) return b * b - 4 * a * c;
  const Real a4 = 4 * a;
  const Real w = a4 * c;
  const Real e = std::fma(-a4, c, w);
  const Real f = std::fma(b, b, -w);
  return f + e;
}

/// Roots of a t² + b t + c = 0 in the numerically stable form: the root of larger magnitude
/// from q = −(b + sign(b)√Δ)/2 avoids cancelling b against √Δ, the other comes from c / q.
/// a == 0 is the linear case (planes; rays along a cylinder's axis). A tangent ray (Δ == 0)
/// gives a double root, never NaN, for finite inputs.
template <class Real>
Roots<Real> solve_quadratic(Real a, Real b, Real c, Discriminant mode = Discriminant::Plain) {
  Roots<Real> r;
  if (a == 0) {
    if (b == 0) return r;
    r.n = 1;
    r.t0 = r.t1 = -c / b;
    return r;
  }
  const Real disc = discriminant(a, b, c, mode);
  if (!(disc >= 0)) return r;  // also rejects NaN
  const Real q = -(b + std::copysign(std::sqrt(disc), b)) / 2;
  if (q == 0) {  // b == 0 and disc == 0, hence c == 0: a double root at zero
    r.n = 2;
    return r;
  }
  Real t0 = q / a, t1 = c / q;
  if (t1 < t0) std::swap(t0, t1);
  r.n = 2;
  r.t0 = t0;
  r.t1 = t1;
  return r;
}

/// Clip test in the machine's precision: is V + t U inside every half-space?
/// The clips must be in the frame the latches are in (world, or the primitive's re-centred frame).
template <class Real>
bool inside_clips(const std::vector<HalfSpace>& clips, const Latches<Real>& l, Real t) {
  if (clips.empty()) return true;
  const Real x = l[kVx] + t * l[kUx], y = l[kVy] + t * l[kUy], z = l[kVz] + t * l[kUz];
  for (const HalfSpace& h : clips) {
    const Real s = static_cast<Real>(h.n.x) * x + static_cast<Real>(h.n.y) * y +
                   static_cast<Real>(h.n.z) * z + static_cast<Real>(h.d);
    if (s > 0) return false;
  }
  return true;
}

struct PrimitiveHit {
  bool hit = false;
  double t = kInf;
  int clip_tests = 0;  ///< half-space evaluations made (each a 3-product dot plus offset)
};

/// The ray's first surface point on this primitive beyond t_min (roots beyond t_min are taken
/// nearest first, skipping clipped ones), reported only if it lies in the window [t_lo, t_hi]
/// (the current voxel): a hit outside the voxel is found again when the ray gets there.
template <class Real>
PrimitiveHit first_hit_in_window(const std::vector<HalfSpace>& clips, const Roots<Real>& roots,
                                 const Latches<Real>& l, double t_min, double t_lo, double t_hi) {
  PrimitiveHit out;
  const Real ts[2] = {roots.t0, roots.t1};
  for (int i = 0; i < roots.n; ++i) {
    const Real t = ts[i];
    if (!(static_cast<double>(t) > t_min)) continue;
    out.clip_tests += static_cast<int>(clips.size());
    if (!inside_clips(clips, l, t)) continue;
    const double td = static_cast<double>(t);
    if (td >= t_lo && td <= t_hi) {
      out.hit = true;
      out.t = td;
    }
    return out;
  }
  return out;
}

template <class Real>
PrimitiveHit first_hit_in_window(const Primitive& p, const Roots<Real>& roots,
                                 const Latches<Real>& l, double t_min, double t_lo, double t_hi) {
  return first_hit_in_window(p.clips, roots, l, t_min, t_lo, t_hi);
}

/// Full intersection of one ray with one primitive in world coordinates.
template <class Real>
PrimitiveHit intersect(const Primitive& p, const CoefRam<Real>& ram, const Latches<Real>& l,
                       double t_min, double t_lo, double t_hi) {
  const Abg<Real> abg = form_abg(l, ram);
  return first_hit_in_window(p.clips, solve_quadratic(abg.a, abg.b, abg.g), l, t_min, t_lo, t_hi);
}

}  // namespace rtm
