// For tests of the shading arithmetic and the units that use it: one glass sphere, one light, and
// a ray hitting the sphere off-centre.
#pragma once

#include <cmath>

#include "render/ray.h"
#include "scene/scene.h"

namespace rtm::test {

/// A glass sphere of radius 1 at (10, 20, 30) under one light: it spawns a shadow, a reflected
/// and a transmitted ray from every hit.
inline Scene glass_sphere_scene() {
  Scene s;
  Material m;
  m.diffuse = 0.5;
  m.specular = 0.3;
  m.transmission = 0.6;
  m.ior = 1.5;
  s.materials.push_back(m);
  s.lights.push_back({{0, 50, 0}, {1, 1, 1}});
  s.primitives.push_back(make_sphere({10, 20, 30}, 1));
  return s;
}

/// A ray at the sphere, off its centre.
inline Ray glass_sphere_ray() {
  Ray r;
  r.origin = {10.3, 20.2, 25};
  r.dir = normalize(Vec3{0.01, -0.02, 1});
  return r;
}

/// The exact near root of |o + t d − c|² = 1 for the ray's unit d.
inline double glass_sphere_t(const Ray& r) {
  const Vec3 oc = r.origin - Vec3{10, 20, 30};
  const double b = dot(oc, r.dir), c = dot(oc, oc) - 1;
  return -b - std::sqrt(b * b - c);
}

}  // namespace rtm::test
