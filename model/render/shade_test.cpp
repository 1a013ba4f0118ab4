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
  shade_hit<float>(h.s, h.ray, h.t, h.s.primitives[0], HitRefine::None, o32);
  shade_hit<double>(h.s, h.ray, h.t, h.s.primitives[0], HitRefine::None, o64);
  ASSERT_EQ(o32.rays.size(), 3u);  // shadow, reflected, transmitted
  ASSERT_EQ(o64.rays.size(), 3u);
  EXPECT_TRUE(is_float(o32.brightness));
  for (size_t i = 0; i < 3; ++i) {
    const Ray &a = o32.rays[i], &b = o64.rays[i];
    EXPECT_EQ(a.kind, b.kind);
    // Origins, directions, contributions and a shadow ray's brightness and length are floats,
    // each within float rounding of the double result, and (here) not all equal to it.
    EXPECT_TRUE(is_float(a.origin) && is_float(a.dir) && is_float(a.contribution) && is_float(a.brightness)) << i;
    EXPECT_TRUE(a.t_max == kInf || is_float(a.t_max)) << i;
    EXPECT_LT(length(a.origin - b.origin), 1e-5 * 30) << i;
    EXPECT_LT(length(a.dir - b.dir), 1e-5) << i;
    EXPECT_NE(a.dir, b.dir) << i << ": the directions round differently";
  }
  // The double unit is the reference's shading, bit for bit.
  ShadeOut ref;
  shade_hit(h.s, h.ray, h.t, h.s.primitives[0], ref);
  ShadeOut newton;
  shade_hit<double>(h.s, h.ray, h.t, h.s.primitives[0], HitRefine::Newton, newton);
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
  EXPECT_LT(std::abs(p.value_at(h.ray.origin + refined * h.ray.dir)), 1e-10);  // one step: about the error squared
  EXPECT_NEAR(refined, h.t, 1e-10);
  // Shading follows the choice: newton shades at the refined point, none at t32.
  ShadeOut none, newton;
  shade_hit<double>(h.s, h.ray, t32, p, HitRefine::None, none);
  shade_hit<double>(h.s, h.ray, t32, p, HitRefine::Newton, newton);
  ShadeOut at_refined, at_t32;
  shade_hit<double>(h.s, h.ray, refined, p, HitRefine::None, at_refined);
  shade_hit<double>(h.s, h.ray, t32, p, HitRefine::None, at_t32);
  ASSERT_EQ(newton.rays.size(), at_refined.rays.size());
  for (size_t i = 0; i < newton.rays.size(); ++i) {
    EXPECT_EQ(newton.rays[i].origin, at_refined.rays[i].origin);
    EXPECT_EQ(none.rays[i].origin, at_t32.rays[i].origin);
    EXPECT_NE(none.rays[i].origin, newton.rays[i].origin);
  }
}

}  // namespace
}  // namespace rtm
