// The shading stage's arithmetic (paper §6), shared by the reference renderer and the machine.
//
// Brightness added to the ray's pixel:
//   a hit by a primary or branch ray: contribution × ka × ambient light × surface colour
//     (primary rays have contribution 1, so this is "the ambient component" for them);
//   a shadow ray that reaches its light: the brightness it was spawned with,
//     contribution × kd × (N·L) × light colour × surface colour;
//   a primary or branch ray that leaves the object space: contribution × background.
// Rays spawned from a hit (into the front buffer):
//   one shadow ray per light in front of the surface (N·L > 0) when kd > 0, contribution × kd;
//   the reflected ray, contribution × ks, and the transmitted ray, contribution × kt, each
//   dropped when its contribution is at or below the threshold or the depth limit is reached.
//
// Templated on the shading unit's arithmetic (`shading_precision`, docs/numerics.md): the hit
// point, the normal, the light and reflection/refraction directions, spawned origins and
// contributions are all formed in Real, from the ray, the scene's lights, materials and quadric
// coefficients rounded to Real. The reference renderer shades in double.
#pragma once

#include <vector>

#include "geom/numerics.h"
#include "render/ray.h"
#include "scene/scene.h"

namespace rtm {

template <class Real>
using Vec3Of = glm::vec<3, Real>;

struct ShadeOut {
  Vec3 brightness{0, 0, 0};
  std::vector<Ray>
      rays;  ///< spawned rays, shadow rays first (in light order), then reflected, transmitted
};

/// The rounding scale of a hit point p on `prim`, as a distance: |p|∞ (where the point itself is
/// rounded: the machine's origin latches hold world coordinates) plus Σ|terms of Q| / |∇Q| in
/// the primitive's centred frame (how far rounding of the quadric's value moves a root), the
/// latter at most the primitive's box diagonal (a vanishing gradient, at a cone's apex).
template <class Real = double>
Real rounding_scale(const Primitive& prim, const Vec3Of<Real>& p);

/// Distance a spawned ray's origin is moved off the surface, so it does not find its own surface
/// again through rounding in t: spawn_offset × max(1, |p|∞) (SpawnPolicy::Relative), or
/// spawn_offset × rounding_scale(prim, p) (SpawnPolicy::Bound: no floor, so tiny objects and thin
/// shells near the origin keep their spawned rays; spawn_offset is then k × the unit roundoff of
/// the machine precision it must cover, 1e-5 ≈ 168 float32 ulps). docs/numerics.md.
template <class Real = double>
Real spawn_offset(const Scene& s, const Primitive& prim, const Vec3Of<Real>& p);

/// The unit surface normal at p facing against the incoming direction d. Where the gradient
/// vanishes (a cone's apex) or is not finite, falls back to −d.
template <class Real = double>
Vec3Of<Real> facing_normal(const Primitive& prim, const Vec3Of<Real>& p, const Vec3Of<Real>& d,
                           bool* entering);

/// The barycentric coordinates of p on a triangle (a polygon of 3 corners, its clips one per edge,
/// geom/quadric.h make_polygon), from the clip tests' edge values: clip k, the edge from corner k
/// to k + 1, is zero on that edge and linear, so its value at p over its value at the opposite
/// corner k + 2 is that corner's weight. In Real, as the shading unit computes them; clamped to
/// [0, 1] and summing to 1. False for a primitive that is not such a triangle.
template <class Real>
bool barycentric(const Primitive& prim, const Vec3Of<Real>& p, Real w[3]);

/// The normal shading lights a hit with, facing the same side as the surface's facing normal
/// `facing`: with NormalInterpolation::Barycentric and vertex normals, their barycentric blend;
/// else `facing` itself.
template <class Real>
Vec3Of<Real> shading_normal(const Primitive& prim, const Vec3Of<Real>& p,
                            const Vec3Of<Real>& facing, NormalInterpolation mode);

/// One Newton step on Q(o + t d) = 0 from the intersection stage's t, in double precision on
/// the primitive's local form (no cancellation far from the origin); the step is limited so a
/// near-tangent ray cannot be thrown far along itself. HitRefine::Newton (geom/numerics.h).
double refine_hit(const Primitive& prim, const Ray& ray, double t);

/// Everything the shading stage does for one ray that hit `prim` at parameter t, in Real, after
/// `refine`, lit with the normal `normals` chooses (spawned rays still leave from the surface's
/// own side, so a blended normal cannot send them through it).
template <class Real>
void shade_hit(const Scene& s, const Ray& ray, double t, const Primitive& prim, HitRefine refine,
               NormalInterpolation normals, ShadeOut& out);

/// The reference renderer's shading: double precision, each hit refined by a Newton step, the
/// normals as the scene's normal_interpolation says.
inline void shade_hit(const Scene& s, const Ray& ray, double t, const Primitive& prim,
                      ShadeOut& out) {
  shade_hit<double>(s, ray, t, prim, HitRefine::Newton, s.normal_interpolation, out);
}

/// Brightness of a primary or branch ray that found nothing.
template <class Real = double>
Vec3 miss_brightness(const Scene& s, const Ray& ray) {
  return Vec3(Real(ray.contribution) * Vec3Of<Real>(s.background));
}

}  // namespace rtm
