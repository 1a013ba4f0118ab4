#include "render/shade.h"

namespace rtm {

double spawn_offset(const Scene& s, const Vec3& p) { return s.spawn_offset * std::max(1.0, max_abs(p)); }

Vec3 facing_normal(const Primitive& prim, const Vec3& p, const Vec3& d, bool* entering) {
  Vec3 n = prim.q.gradient(p);
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

double refine_hit(const Quadric& q, const Ray& ray, double t) {
  const Vec3 p = ray.origin + t * ray.dir;
  const double slope = dot(q.gradient(p), ray.dir);
  if (!(std::abs(slope) > 0)) return t;
  const double step = q.value(p) / slope;
  const double limit = 1e-3 * std::max(1.0, std::abs(t));
  return std::isfinite(step) && std::abs(step) <= limit ? t - step : t;
}

void shade_hit(const Scene& s, const Ray& ray, double t, const Primitive& prim, ShadeOut& out) {
  const Material& m = s.materials[size_t(prim.material)];
  if (s.refine_hits) t = refine_hit(prim.q, ray, t);
  const Vec3 p = ray.origin + t * ray.dir;
  bool entering = true;
  const Vec3 n = facing_normal(prim, p, ray.dir, &entering);
  const double eps = spawn_offset(s, p);
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
