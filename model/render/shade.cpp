#include "render/shade.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace rtm {
namespace {

/// ∇Q at a world point in Real: from the primitive's local form when it has one (its origin and
/// coefficients rounded to Real), else from the world form. In double, Primitive::gradient_at.
template <class Real>
Vec3Of<Real> gradient_at(const Primitive& prim, const Vec3Of<Real>& p) {
  const Quadric& q = prim.has_local ? prim.local : prim.q;
  const Vec3Of<Real> x = prim.has_local ? p - Vec3Of<Real>(prim.origin) : p;
  auto k = [&](Coef i) { return Real(q.c[i]); };
  return {2 * k(kA) * x.x + k(kD) * x.y + k(kF) * x.z + k(kG),
          2 * k(kB) * x.y + k(kD) * x.x + k(kE) * x.z + k(kH),
          2 * k(kC) * x.z + k(kE) * x.y + k(kF) * x.x + k(kI)};
}

}  // namespace

template <class Real>
Real rounding_scale(const Primitive& prim, const Vec3Of<Real>& p) {
  using V = Vec3Of<Real>;
  const Vec3 mid = 0.5 * (prim.bounds.lo + prim.bounds.hi);
  const Quadric q = prim.about(mid);  // the host's: each primitive's centred coefficients
  const V c(mid);
  const V x = p - c;
  auto k = [&](Coef i) { return Real(q.c[i]); };
  const Real terms =
      std::abs(k(kA) * x.x * x.x) + std::abs(k(kB) * x.y * x.y) + std::abs(k(kC) * x.z * x.z) +
      std::abs(k(kD) * x.x * x.y) + std::abs(k(kE) * x.y * x.z) + std::abs(k(kF) * x.z * x.x) +
      std::abs(k(kG) * x.x) + std::abs(k(kH) * x.y) + std::abs(k(kI) * x.z) + std::abs(k(kJ));
  const Real diag = Real(length(prim.bounds.extent()));
  const V g = {2 * k(kA) * x.x + k(kD) * x.y + k(kF) * x.z + k(kG),
               2 * k(kB) * x.y + k(kD) * x.x + k(kE) * x.z + k(kH),
               2 * k(kC) * x.z + k(kE) * x.y + k(kF) * x.x + k(kI)};
  const Real grad = length(g);
  const Real local = grad > 0 && std::isfinite(terms / grad) ? std::min(terms / grad, diag) : diag;
  return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) + local;
}

template <class Real>
Real spawn_offset(const Scene& s, const Primitive& prim, const Vec3Of<Real>& p) {
  if (s.spawn_policy == SpawnPolicy::Bound)
    return Real(s.spawn_offset) * rounding_scale<Real>(prim, p);
  return Real(s.spawn_offset) *
         std::max(Real(1), std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
}

template <class Real>
Vec3Of<Real> facing_normal(const Primitive& prim, const Vec3Of<Real>& p, const Vec3Of<Real>& d,
                           bool* entering) {
  Vec3Of<Real> n = gradient_at<Real>(prim, p);
  // Scaled first when tiny or huge, so |n|² can neither underflow nor overflow (near a cone's
  // apex the gradient goes to zero; a subnormal |n|² would give a normal that is not unit length).
  // The bounds are well inside Real's range either way: 1e±150 in double, 1e±18 in float.
  constexpr Real kTiny = std::is_same_v<Real, double> ? Real(1e-150) : Real(1e-18);
  constexpr Real kHuge = std::is_same_v<Real, double> ? Real(1e150) : Real(1e18);
  const Real m = std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
  if (m > 0 && std::isfinite(m) && (m < kTiny || m > kHuge)) n /= m;
  const Real len = length(n);
  if (!(len > 0) || !std::isfinite(len)) {
    if (entering) *entering = true;
    return -normalize(d);
  }
  n /= len;
  const bool in = dot(n, d) < 0;  // against the gradient: from Q > 0 (outside) into Q < 0
  if (entering) *entering = in;
  return in ? n : -n;
}

template <class Real>
bool barycentric(const Primitive& prim, const Vec3Of<Real>& p, Real w[3]) {
  using V = Vec3Of<Real>;
  if (prim.kind != ShapeKind::Polygon || prim.vertices.size() != 3 || prim.clips.size() != 3)
    return false;
  Real sum = 0;
  for (int k = 0; k < 3; ++k) {
    const HalfSpace& h = prim.clips[size_t(k)];
    auto edge = [&](const V& x) {
      return dot(V(h.n), x) + Real(h.d);
    };  // as the clip test forms it
    // Inside, the clip values are <= 0; the opposite corner's is the most negative.
    const Real at = edge(p), corner = edge(V(prim.vertices[size_t((k + 2) % 3)]));
    Real x = corner < 0 ? at / corner : Real(0);
    x = std::isfinite(x) ? std::clamp(x, Real(0), Real(1)) : Real(0);
    w[(k + 2) % 3] = x;
    sum += x;
  }
  if (!(sum > 0)) return false;
  for (int k = 0; k < 3; ++k) w[k] /= sum;
  return true;
}

template <class Real>
Vec3Of<Real> shading_normal(const Primitive& prim, const Vec3Of<Real>& p,
                            const Vec3Of<Real>& facing, NormalInterpolation mode) {
  using V = Vec3Of<Real>;
  Real w[3];
  if (mode != NormalInterpolation::Barycentric || prim.normals.size() != 3 ||
      !barycentric<Real>(prim, p, w))
    return facing;
  const V n = w[0] * V(prim.normals[0]) + w[1] * V(prim.normals[1]) + w[2] * V(prim.normals[2]);
  const Real len = length(n);
  if (!(len > 0) || !std::isfinite(len)) return facing;  // opposed vertex normals
  return dot(n, facing) < 0 ? -n / len : n / len;
}

double refine_hit(const Primitive& prim, const Ray& ray, double t) {
  const Vec3 p = ray.origin + t * ray.dir;
  const double slope = dot(prim.gradient_at(p), ray.dir);
  if (!(std::abs(slope) > 0)) return t;
  const double step = prim.value_at(p) / slope;
  const double limit = 1e-3 * std::max(1.0, std::abs(t));
  return std::isfinite(step) && std::abs(step) <= limit ? t - step : t;
}

template <class Real>
void shade_hit(const Scene& s, const Ray& ray, double t_hit, const Primitive& prim,
               HitRefine refine, NormalInterpolation normals, ShadeOut& out) {
  using V = Vec3Of<Real>;
  const Material& m = s.materials[size_t(prim.material)];
  const Real t = Real(refine == HitRefine::Newton ? refine_hit(prim, ray, t_hit) : t_hit);
  const V d(ray.dir);
  const V p = V(ray.origin) + t * d;
  bool entering = true;
  const V surface = facing_normal<Real>(prim, p, d, &entering);
  const V n = shading_normal<Real>(prim, p, surface, normals);
  const Real eps = spawn_offset<Real>(s, prim, p);
  const V above = p + eps * surface, below = p - eps * surface;
  const V color(m.color);
  const Real contribution = Real(ray.contribution);

  out.brightness = Vec3(contribution * Real(m.ambient) * V(s.ambient_light) * color);
  out.rays.clear();

  // Shadow rays: one per light the surface faces.
  if (m.diffuse > 0) {
    for (const Light& light : s.lights) {
      const V to_light = V(light.position) - above;
      const Real dist = length(to_light);
      if (!(dist > 0)) continue;
      const V l = to_light / dist;
      const Real ndl = dot(n, l);
      if (ndl <= 0 || dot(surface, l) <= 0)
        continue;  // a light behind the surface itself is hidden by it
      Ray r;
      r.kind = RayKind::Shadow;
      r.origin = Vec3(above);
      r.dir = Vec3(l);
      r.t_max = dist;
      const Real c = contribution * Real(m.diffuse);
      r.contribution = c;
      r.brightness = Vec3(c * ndl * V(light.color) * color);
      r.pixel = ray.pixel;
      r.depth = ray.depth;
      out.rays.push_back(r);
    }
  }
  if (ray.depth >= s.max_depth) return;

  // Reflected ray.
  const Real c_refl = contribution * Real(m.specular);
  if (c_refl > Real(s.threshold)) {
    Ray r;
    r.kind = RayKind::Reflected;
    r.origin = Vec3(above);
    r.dir = Vec3(normalize(d - 2 * dot(d, n) * n));
    r.contribution = c_refl;
    r.pixel = ray.pixel;
    r.depth = uint8_t(ray.depth + 1);
    out.rays.push_back(r);
  }

  // Transmitted ray (Snell); none under total internal reflection.
  const Real c_trans = contribution * Real(m.transmission);
  if (c_trans > Real(s.threshold)) {
    const Real ior = Real(m.ior);
    const Real eta = entering ? 1 / ior : ior;
    const Real cos_i = -dot(d, n);
    const Real k = 1 - eta * eta * (1 - cos_i * cos_i);
    if (k >= 0) {
      Ray r;
      r.kind = RayKind::Transmitted;
      r.origin = Vec3(below);
      r.dir = Vec3(normalize(eta * d + (eta * cos_i - std::sqrt(k)) * n));
      r.contribution = c_trans;
      r.pixel = ray.pixel;
      r.depth = uint8_t(ray.depth + 1);
      out.rays.push_back(r);
    }
  }
}

// The two precisions of a shading unit (shading_precision).
template float rounding_scale<float>(const Primitive&, const Vec3Of<float>&);
template double rounding_scale<double>(const Primitive&, const Vec3Of<double>&);
template float spawn_offset<float>(const Scene&, const Primitive&, const Vec3Of<float>&);
template double spawn_offset<double>(const Scene&, const Primitive&, const Vec3Of<double>&);
template Vec3Of<float> facing_normal<float>(const Primitive&, const Vec3Of<float>&,
                                            const Vec3Of<float>&, bool*);
template Vec3Of<double> facing_normal<double>(const Primitive&, const Vec3Of<double>&,
                                              const Vec3Of<double>&, bool*);
template bool barycentric<float>(const Primitive&, const Vec3Of<float>&, float[3]);
template bool barycentric<double>(const Primitive&, const Vec3Of<double>&, double[3]);
template Vec3Of<float> shading_normal<float>(const Primitive&, const Vec3Of<float>&,
                                             const Vec3Of<float>&, NormalInterpolation);
template Vec3Of<double> shading_normal<double>(const Primitive&, const Vec3Of<double>&,
                                               const Vec3Of<double>&, NormalInterpolation);
template void shade_hit<float>(const Scene&, const Ray&, double, const Primitive&, HitRefine,
                               NormalInterpolation, ShadeOut&);
template void shade_hit<double>(const Scene&, const Ray&, double, const Primitive&, HitRefine,
                                NormalInterpolation, ShadeOut&);

}  // namespace rtm
