// The shading arithmetic in both of a shading unit's precisions (shading_precision) and the hit
// refinement (hit_refine), on hand-built hits.
#include "render/shade.h"

#include "render/glass_sphere_test_scene.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rtm {
namespace {

bool is_float(double x) { return double(float(x)) == x; }
bool is_float(const Vec3& v) { return is_float(v.x) && is_float(v.y) && is_float(v.z); }

/// The glass sphere and a ray hitting it off-centre, at its exact t.
struct Hit {
  Scene s = test::glass_sphere_scene();
  Ray ray = test::glass_sphere_ray();
  double t = test::glass_sphere_t(ray);
};

TEST(ShadePrecision, Fp32FormsEveryShadingResultInFloat) {
  const Hit h;
  ShadeOut o32, o64;
  shade_hit<float>(h.s, h.ray, h.t, h.s.primitives[0], HitRefine::None, NormalInterpolation::Flat,
                   o32);
  shade_hit<double>(h.s, h.ray, h.t, h.s.primitives[0], HitRefine::None, NormalInterpolation::Flat,
                    o64);
  ASSERT_EQ(o32.rays.size(), 3u);  // shadow, reflected, transmitted
  ASSERT_EQ(o64.rays.size(), 3u);
  EXPECT_TRUE(is_float(o32.brightness));
  for (size_t i = 0; i < 3; ++i) {
    const Ray &a = o32.rays[i], &b = o64.rays[i];
    EXPECT_EQ(a.kind, b.kind);
    // Origins, directions, contributions and a shadow ray's brightness and length are floats,
    // each within float rounding of the double result, and (here) not all equal to it.
    EXPECT_TRUE(is_float(a.origin) && is_float(a.dir) && is_float(a.contribution) &&
                is_float(a.brightness))
        << i;
    EXPECT_TRUE(a.t_max == kInf || is_float(a.t_max)) << i;
    EXPECT_LT(length(a.origin - b.origin), 1e-5 * 30) << i;
    EXPECT_LT(length(a.dir - b.dir), 1e-5) << i;
    EXPECT_NE(a.dir, b.dir) << i << ": the directions round differently";
  }
  // The double unit is the reference's shading, bit for bit.
  ShadeOut ref;
  shade_hit(h.s, h.ray, h.t, h.s.primitives[0], ref);
  ShadeOut newton;
  shade_hit<double>(h.s, h.ray, h.t, h.s.primitives[0], HitRefine::Newton,
                    NormalInterpolation::Flat, newton);
  ASSERT_EQ(ref.rays.size(), newton.rays.size());
  for (size_t i = 0; i < ref.rays.size(); ++i) {
    EXPECT_EQ(ref.rays[i].origin, newton.rays[i].origin);
    EXPECT_EQ(ref.rays[i].dir, newton.rays[i].dir);
  }
}

TEST(ShadePrecision, TheNormalFallsBackInFloatToo) {
  // A cone's apex: ∇Q = 0, the normal is −d in either precision; 1e-30 from it |∇Q|² underflows
  // float, and the gradient is scaled before it is normalised.
  const Primitive cone = make_cone({0, 0, 0}, 1, {0, 0, 2}, 0);
  const Vec3Of<float> d = normalize(Vec3Of<float>{0.3f, -0.4f, -1});
  for (const Vec3Of<float>& p : {Vec3Of<float>{0, 0, 2}, Vec3Of<float>{1e-30f, 0, 2 - 0.5e-30f}}) {
    const Vec3Of<float> n = facing_normal<float>(cone, p, d, nullptr);
    EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    EXPECT_NEAR(length(n), 1, 1e-6);
    EXPECT_LE(dot(n, d), 0);
  }
}

TEST(HitRefine, NewtonPutsAFloatTOnTheSurfaceAndNoneLeavesIt) {
  // t as a float32 root unit gives it: off the surface by about an ulp of t times |d|.
  const Hit h;
  const double t32 = double(float(h.t) * (1 + 4e-7f));
  const Primitive& p = h.s.primitives[0];
  const double off = std::abs(p.value_at(h.ray.origin + t32 * h.ray.dir));
  const double refined = refine_hit(p, h.ray, t32);
  EXPECT_GT(off, 1e-7);
  EXPECT_LT(std::abs(p.value_at(h.ray.origin + refined * h.ray.dir)),
            1e-10);  // one step: about the error squared
  EXPECT_NEAR(refined, h.t, 1e-10);
  // Shading follows the choice: newton shades at the refined point, none at t32.
  ShadeOut none, newton;
  shade_hit<double>(h.s, h.ray, t32, p, HitRefine::None, NormalInterpolation::Flat, none);
  shade_hit<double>(h.s, h.ray, t32, p, HitRefine::Newton, NormalInterpolation::Flat, newton);
  ShadeOut at_refined, at_t32;
  shade_hit<double>(h.s, h.ray, refined, p, HitRefine::None, NormalInterpolation::Flat, at_refined);
  shade_hit<double>(h.s, h.ray, t32, p, HitRefine::None, NormalInterpolation::Flat, at_t32);
  ASSERT_EQ(newton.rays.size(), at_refined.rays.size());
  for (size_t i = 0; i < newton.rays.size(); ++i) {
    EXPECT_EQ(newton.rays[i].origin, at_refined.rays[i].origin);
    EXPECT_EQ(none.rays[i].origin, at_t32.rays[i].origin);
    EXPECT_NE(none.rays[i].origin, newton.rays[i].origin);
  }
}

/// A triangle in z = 0 with corners (0,0,0), (2,0,0), (0,2,0), tilted vertex normals, lit from
/// straight above; a ray straight down at (x, y).
struct SmoothTriangle {
  Scene s;
  SmoothTriangle() {
    Primitive p = make_polygon({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}});
    p.normals = vertex_normals(p, {{-1, 0, 1}, {1, 0, 1}, {0, 1, 1}});
    s.primitives = {p};
    s.materials = {Material{}};
    s.materials[0].ambient = 0;
    s.lights = {{{0.5, 0.5, 100}, {1, 1, 1}}};
  }
  Ray down(double x, double y) const {
    Ray r;
    r.origin = {x, y, 10};
    r.dir = {0, 0, -1};
    return r;
  }
};

TEST(SmoothShading, BarycentricCoordinatesComeFromTheClipValues) {
  const SmoothTriangle t;
  double w[3];
  ASSERT_TRUE(barycentric<double>(t.s.primitives[0], {0.5, 0.5, 0}, w));
  EXPECT_NEAR(w[0], 0.5, 1e-15);                                      // 1 - x/2 - y/2
  EXPECT_NEAR(w[1], 0.25, 1e-15);                                     // x / 2
  EXPECT_NEAR(w[2], 0.25, 1e-15);                                     // y / 2
  ASSERT_TRUE(barycentric<double>(t.s.primitives[0], {2, 0, 0}, w));  // a corner: all its own
  EXPECT_NEAR(w[1], 1, 1e-15);
  float f[3];
  ASSERT_TRUE(barycentric<float>(t.s.primitives[0], {0.5f, 0.5f, 0}, f));
  EXPECT_NEAR(f[1], 0.25f, 1e-7f);
  EXPECT_FALSE(barycentric<double>(make_sphere({0, 0, 0}, 1), {1, 0, 0}, w));
}

TEST(SmoothShading, FlatIsThePlanesNormalBarycentricTheVertexNormalsBlend) {
  const SmoothTriangle t;
  const Primitive& p = t.s.primitives[0];
  const Vec3 up(0, 0, 1);
  // Flat, or a triangle without vertex normals: the plane's normal, wherever the hit is.
  EXPECT_EQ(shading_normal<double>(p, {0.5, 0.5, 0}, up, NormalInterpolation::Flat), up);
  Primitive bare = p;
  bare.normals.clear();
  EXPECT_EQ(shading_normal<double>(bare, {0.5, 0.5, 0}, up, NormalInterpolation::Barycentric), up);
  // Barycentric: at a corner its own normal; between, the normalised blend.
  const Vec3 at_corner = shading_normal<double>(p, {2, 0, 0}, up, NormalInterpolation::Barycentric);
  EXPECT_NEAR(at_corner.x, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(at_corner.z, std::sqrt(0.5), 1e-12);
  const Vec3 mid = shading_normal<double>(p, {0.5, 0.5, 0}, up, NormalInterpolation::Barycentric);
  const Vec3 blend = normalize(0.5 * p.normals[0] + 0.25 * p.normals[1] + 0.25 * p.normals[2]);
  EXPECT_NEAR(length(mid - blend), 0, 1e-12);
  // Seen from below, the blend faces the ray as the plane's normal does.
  EXPECT_LT(shading_normal<double>(p, {0.5, 0.5, 0}, -up, NormalInterpolation::Barycentric).z, 0);
}

// Lit from above: flat shading gives every point of the triangle the same brightness; barycentric
// gives each the cosine of its blended normal, in either shading precision, and its shadow ray
// the same brightness as its pixel's.
TEST(SmoothShading, TheShadowRaysCarryTheBlendedNormalsBrightness) {
  const SmoothTriangle t;
  auto shadow = [&](double x, double y, NormalInterpolation mode, bool fp32) {
    ShadeOut out;
    const Ray r = t.down(x, y);
    if (fp32)
      shade_hit<float>(t.s, r, 10, t.s.primitives[0], HitRefine::None, mode, out);
    else
      shade_hit<double>(t.s, r, 10, t.s.primitives[0], HitRefine::None, mode, out);
    EXPECT_EQ(out.rays.size(), 1u);
    return out.rays.empty() ? -1.0 : out.rays[0].brightness.x;
  };
  const double kd = t.s.materials[0].diffuse;
  const Vec3 l = normalize(Vec3(0.5, 0.5, 100) - Vec3(0.2, 0.2, 0));
  // The shadow ray leaves from spawn_offset above the hit: its direction differs by ~1e-7.
  EXPECT_NEAR(shadow(0.2, 0.2, NormalInterpolation::Flat, false), kd * l.z, 1e-9);
  EXPECT_NEAR(shadow(1.2, 0.3, NormalInterpolation::Flat, false),
              kd * normalize(Vec3(0.5, 0.5, 100) - Vec3(1.2, 0.3, 0)).z,
              1e-9);  // the plane's normal there too
  const Primitive& p = t.s.primitives[0];
  const Vec3 n =
      shading_normal<double>(p, {0.2, 0.2, 0}, {0, 0, 1}, NormalInterpolation::Barycentric);
  EXPECT_NEAR(shadow(0.2, 0.2, NormalInterpolation::Barycentric, false), kd * dot(n, l), 1e-9);
  EXPECT_NEAR(shadow(0.2, 0.2, NormalInterpolation::Barycentric, true), kd * dot(n, l), 1e-6);
  // Near the tilted corner (0, 0) and near the middle: the normal turns across the triangle.
  EXPECT_GT(shadow(0.6, 0.6, NormalInterpolation::Barycentric, false) -
                shadow(0.1, 0.1, NormalInterpolation::Barycentric, false),
            0.1);
}

}  // namespace
}  // namespace rtm
