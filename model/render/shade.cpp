#include "render/shade.h"

namespace rtm {

double rounding_scale(const Primitive& prim, const Vec3& p) {
  const Vec3 c = 0.5 * (prim.bounds.lo + prim.bounds.hi);
  const Quadric q = prim.about(c);
  const Vec3 x = p - c;
  const auto& k = q.c;
  const double terms = std::abs(k[kA] * x.x * x.x) + std::abs(k[kB] * x.y * x.y) + std::abs(k[kC] * x.z * x.z) +
                       std::abs(k[kD] * x.x * x.y) + std::abs(k[kE] * x.y * x.z) + std::abs(k[kF] * x.z * x.x) +
                       std::abs(k[kG] * x.x) + std::abs(k[kH] * x.y) + std::abs(k[kI] * x.z) + std::abs(k[kJ]);
  const double diag = length(prim.bounds.extent());
  const double grad = length(q.gradient(x));
  const double local = grad > 0 && std::isfinite(terms / grad) ? std::min(terms / grad, diag) : diag;
  return max_abs(p) + local;
}

double spawn_offset(const Scene& s, const Primitive& prim, const Vec3& p) {
  if (s.spawn_policy == SpawnPolicy::Bound) return s.spawn_offset * rounding_scale(prim, p);
  return s.spawn_offset * std::max(1.0, max_abs(p));
}

Vec3 facing_normal(const Primitive& prim, const Vec3& p, const Vec3& d, bool* entering) {
  Vec3 n = prim.gradient_at(p);
  // Scaled first when tiny or huge, so |n|² can neither underflow nor overflow (near a cone's
  // apex the gradient goes to zero; a subnormal |n|² would give a normal that is not unit length).
  const double m = max_abs(n);
  if (m > 0 && std::isfinite(m) && (m < 1e-150 || m > 1e150)) n /= m;
  const double len = length(n);
  if (!(len > 0) || !std::isfinite(len)) {
    if (entering) *entering = true;
    return -normalize(d);
  }
  n /= len;
  const bool in = dot(n, d) < 0;  // against the gradient: from Q > 0 (outside) into Q < 0
  if (entering) *entering = in;
  return in ? n : -n;
}

double refine_hit(const Primitive& prim, const Ray& ray, double t) {
  const Vec3 p = ray.origin + t * ray.dir;
  const double slope = dot(prim.gradient_at(p), ray.dir);
  if (!(std::abs(slope) > 0)) return t;
  const double step = prim.value_at(p) / slope;
  const double limit = 1e-3 * std::max(1.0, std::abs(t));
  return std::isfinite(step) && std::abs(step) <= limit ? t - step : t;
}

void shade_hit(const Scene& s, const Ray& ray, double t, const Primitive& prim, ShadeOut& out) {
  const Material& m = s.materials[size_t(prim.material)];
  if (s.refine_hits) t = refine_hit(prim, ray, t);
  const Vec3 p = ray.origin + t * ray.dir;
  bool entering = true;
  const Vec3 n = facing_normal(prim, p, ray.dir, &entering);
  const double eps = spawn_offset(s, prim, p);
  const Vec3 above = p + eps * n, below = p - eps * n;

  out.brightness = ray.contribution * m.ambient * s.ambient_light * m.color;
  out.rays.clear();

  // Shadow rays: one per light the surface faces.
  if (m.diffuse > 0) {
    for (const Light& light : s.lights) {
      const Vec3 to_light = light.position - above;
      const double dist = length(to_light);
      if (!(dist > 0)) continue;
      const Vec3 l = to_light / dist;
      const double ndl = dot(n, l);
      if (ndl <= 0) continue;
      Ray r;
      r.kind = RayKind::Shadow;
      r.origin = above;
      r.dir = l;
      r.t_max = dist;
      r.contribution = ray.contribution * m.diffuse;
      r.brightness = r.contribution * ndl * light.color * m.color;
      r.pixel = ray.pixel;
      r.depth = ray.depth;
      out.rays.push_back(r);
    }
  }
  if (ray.depth >= s.max_depth) return;

  // Reflected ray.
  const double c_refl = ray.contribution * m.specular;
  if (c_refl > s.threshold) {
    Ray r;
    r.kind = RayKind::Reflected;
    r.origin = above;
    r.dir = normalize(ray.dir - 2 * dot(ray.dir, n) * n);
    r.contribution = c_refl;
    r.pixel = ray.pixel;
    r.depth = uint8_t(ray.depth + 1);
    out.rays.push_back(r);
  }

  // Transmitted ray (Snell); none under total internal reflection.
  const double c_trans = ray.contribution * m.transmission;
  if (c_trans > s.threshold) {
    const double eta = entering ? 1.0 / m.ior : m.ior;
    const double cos_i = -dot(ray.dir, n);
    const double k = 1 - eta * eta * (1 - cos_i * cos_i);
    if (k >= 0) {
      Ray r;
      r.kind = RayKind::Transmitted;
      r.origin = below;
      r.dir = normalize(eta * ray.dir + (eta * cos_i - std::sqrt(k)) * n);
      r.contribution = c_trans;
      r.pixel = ray.pixel;
      r.depth = uint8_t(ray.depth + 1);
      out.rays.push_back(r);
    }
  }
}

}  // namespace rtm
