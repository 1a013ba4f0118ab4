// The error attribution on constructed scenes whose cause is known: rays aimed ever closer to a
// silhouette or a shadow's edge until the float machine and the double reference disagree, and a
// thin mirror cylinder whose float normals turn the reflected rays. The attribution must name the
// cause the construction put there, and every tree it traces must sum to its pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>

#include "error/error_causes.h"
#include "error/pe_tracer.h"

namespace rtm {

void PrintTo(ErrorCause c, std::ostream* os) { *os << error_cause_name(c); }

namespace {

MachineConfig fp32_machine() {
  MachineConfig c;
  set_config_assignment(c, "precision=fp32");
  return c;
}

struct Traced {
  Scene scene;
  Grid grid;
  MachineConfig config = fp32_machine();
  std::optional<PeTracer> pe;
  std::optional<ReferenceTracer> ref;
  explicit Traced(Scene s)
      : scene(std::move(s)), grid(build_grid(scene.primitives, scene.grid, 1)) {
    pe.emplace(scene, grid, config);
    ref.emplace(scene, grid);
  }
  double tolerance() const { return kHitPointTolerance * length(grid.box.hi - grid.box.lo); }
  PixelCause explain(const Ray& primary) {
    return explain_pixel(primary, *pe, *ref, tolerance(), traced_pixel(*pe, primary),
                         traced_pixel(*ref, primary));
  }
  RayResult first(RayTracer& t, const Ray& ray) {
    RayResult out;
    t.trace(ray, out);
    return out;
  }
};

Ray primary(const Vec3& origin, const Vec3& towards) {
  Ray r;
  r.origin = origin;
  r.dir = normalize(towards - origin);
  return r;
}

/// The first (k, j), k in 1..40 and j in 0..31, for which `parts` holds; fails the test if none
/// does. k: how close to the edge (2^-k); j: where along it (rounding differs from place to place).
std::pair<int, int> first_parting(const std::function<bool(int, int)>& parts) {
  for (int k = 1; k <= 40; ++k)
    for (int j = 0; j < 32; ++j)
      if (parts(k, j)) return {k, j};
  ADD_FAILURE() << "no construction parted the float machine from the reference";
  return {0, 0};
}

// A sphere far from the eye, and rays passing 2^-k of its radius inside its silhouette: the
// reference hits each; the float machine, whose ray directions are rounded, misses some.
TEST(ErrorCauses, ARayGrazingASphereThatFloatMissesIsMissed) {
  Scene s;
  s.materials.push_back(Material{});
  s.lights.push_back({{3000, 3000, 2000}, {1, 1, 1}});
  const Vec3 c{3000, 2000, 1000};
  s.primitives.push_back(make_sphere(c, 1));
  Traced t(s);
  auto ray = [&](int k, int j) {
    const double a = 0.05 * j, r = 1 - std::ldexp(1.0, -k);
    const Vec3 beside =
        c + r * normalize(cross(Vec3{3000, 2000, 1000}, Vec3{std::cos(a), std::sin(a), 0}));
    return primary(beside - Vec3{3000, 2000, 1000} + Vec3{1e-3 * j, 0, 0}, beside);
  };
  const auto [k, j] = first_parting([&](int k, int j) {
    return t.first(*t.ref, ray(k, j)).end == RayResult::End::Hit &&
           t.first(*t.pe, ray(k, j)).end == RayResult::End::Missed;
  });
  const PixelCause p = t.explain(ray(k, j));
  EXPECT_EQ(p.cause, ErrorCause::Missed);
  EXPECT_EQ(p.generation, 1);
  EXPECT_EQ(p.kind, RayKind::Primary);
  EXPECT_EQ(p.prim, -1);
  EXPECT_EQ(p.reference_prim, 0);
}

// A floor, a light, and a small sphere between them, far from the origin; primary rays hit the
// floor ever closer to the shadow's edge (2^-k of the sphere's radius, on either side): near it,
// some shadow ray reaches the light in the reference and is blocked in the float machine, whose
// shadow rays start from float hit points.
TEST(ErrorCauses, AShadowRayBlockedOnlyInFloatIsShadowBlocked) {
  Scene s;
  s.materials.push_back(Material{});
  const Vec3 light{2000, 2100, 1000}, ball{2000, 2050, 1000};
  s.lights.push_back({light, {1, 1, 1}});
  s.primitives.push_back(make_plane({0, 1, 0}, -2000, {{1900, 1999, 900}, {2100, 2001, 1100}}));
  s.primitives.push_back(make_sphere(ball, 1));
  Traced t(s);
  const Vec3 eye{2000, 2020, 960};
  // The floor point whose line to the light passes `miss` from the ball's centre, beside it in x.
  auto floor_point = [&](double miss, double a) {
    const double l = light.y - ball.y, r = miss * l / std::sqrt(l * l - miss * miss);
    const Vec3 beside = ball + Vec3{r * std::cos(a), 0, r * std::sin(a)};
    const Vec3 d = beside - light;
    return light + d * ((2000 - light.y) / d.y);
  };
  // Even j: outside the shadow, odd j: inside it.
  auto ray = [&](int k, int j) {
    return primary(eye, floor_point(1 + (j % 2 ? -1 : 1) * std::ldexp(1.0, -k), 0.05 * (j / 2)));
  };
  auto shadow = [&](RayTracer& tr, const Ray& r) {
    const RayResult hit = t.first(tr, r);
    return hit.end == RayResult::End::Hit && !hit.spawned.empty() ? t.first(tr, hit.spawned[0]).end
                                                                  : RayResult::End::Missed;
  };
  const auto [k, j] = first_parting([&](int k, int j) {
    return shadow(*t.ref, ray(k, j)) == RayResult::End::LightReached &&
           shadow(*t.pe, ray(k, j)) == RayResult::End::Blocked;
  });
  const PixelCause p = t.explain(ray(k, j));
  EXPECT_EQ(p.cause, ErrorCause::ShadowBlocked);
  EXPECT_EQ(p.generation, 2);
  EXPECT_EQ(p.kind, RayKind::Shadow);
  EXPECT_EQ(p.prim, 1);
  EXPECT_EQ(p.reference_prim, -1);
}

// A thin mirror cylinder and a ball beside it: primary rays across the cylinder hit it in both
// renderers, but its float normals (a hit point's rounding over a radius of 0.01) turn the
// reflected rays, and where those sweep over the ball's edge, one side's reflection hits it and
// the other's does not. The pixel's cause is the reflected ray, not the primary ray's hit.
TEST(ErrorCauses, AReflectionOffAThinCylinderPartsAtTheReflectedRay) {
  Scene s;
  Material mirror;
  mirror.diffuse = 0;
  mirror.specular = 0.9;
  s.materials = {mirror, Material{}};
  s.lights.push_back({{0, 100, 0}, {1, 1, 1}});
  const Vec3 axis{30, 20, 10};
  s.primitives.push_back(make_cone(axis - Vec3{0, 1, 0}, 0.01, axis + Vec3{0, 1, 0}, 0.01));
  s.primitives.push_back(make_sphere(axis + Vec3{-20, 0, -40}, 5));
  s.primitives[1].material = 1;
  Traced t(s);
  const Vec3 eye = axis + Vec3{0, 0, -30};
  // Across the middle 90 % of its width: nearer its edges, rays graze it and may miss.
  auto ray = [&](int i) { return primary(eye, axis + Vec3{0.009 * (i / 5000.0 - 1), 0, 0}); };
  auto reflection = [&](RayTracer& tr, const Ray& r) {
    const RayResult hit = t.first(tr, r);
    EXPECT_EQ(hit.end, RayResult::End::Hit);
    EXPECT_EQ(hit.prim, 0u);
    EXPECT_EQ(hit.spawned.size(), 1u);
    return hit.spawned.empty() ? RayResult{} : t.first(tr, hit.spawned[0]);
  };
  int parted = 0;
  for (int i = 1; i < 10000; ++i) {
    const RayResult m = reflection(*t.pe, ray(i)), r = reflection(*t.ref, ray(i));
    if (m.end == r.end && (m.end != RayResult::End::Hit || m.prim == r.prim)) continue;
    ++parted;
    const PixelCause p = t.explain(ray(i));
    EXPECT_EQ(p.cause, m.end == RayResult::End::Hit ? ErrorCause::ExtraHit : ErrorCause::Missed)
        << "ray " << i;
    EXPECT_EQ(p.generation, 2) << "ray " << i;
    EXPECT_EQ(p.kind, RayKind::Reflected) << "ray " << i;
  }
  EXPECT_GT(parted, 0) << "no reflected ray parted the float machine from the reference";
}

// A count difference is the differing pixels' own only when their trees hold all of it: the
// rest was done on pixels that agree within 1/255.
TEST(ErrorCauses, ACountGapIsExplainedOnlyWhenTheDifferingPixelsTreesHoldAllOfIt) {
  TraceCounts machine, reference;
  machine.rays = {16, 30, 4, 2};
  reference.rays = {16, 28, 4, 5};
  machine.voxel_steps = 1007;
  reference.voxel_steps = 1000;
  ErrorCauses e;
  e.differing = 2;
  e.trees.machine.rays = {2, 5, 0, 0};  // the two pixels: 2 more shadow rays, 3 fewer transmitted
  e.trees.reference.rays = {2, 3, 0, 3};
  e.trees.machine.voxel_steps = e.trees.reference.voxel_steps = 40;  // none of the 7 voxel steps
  const std::vector<CountGap> g = count_gaps(machine, reference, e);
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0].count.what, "shadow rays");
  EXPECT_EQ(g[0].difference(), 2);
  EXPECT_EQ(g[0].in_trees, 2);
  EXPECT_TRUE(g[0].explained);
  EXPECT_EQ(g[1].count.what, "transmitted rays");
  EXPECT_EQ(g[1].difference(), -3);
  EXPECT_TRUE(g[1].explained);
  EXPECT_EQ(g[2].count.what, "voxel steps");
  EXPECT_EQ(g[2].in_trees, 0);
  EXPECT_FALSE(g[2].explained);
  // A tree that could not be traced whole explains nothing.
  e.trees_whole = false;
  for (const CountGap& x : count_gaps(machine, reference, e))
    EXPECT_FALSE(x.explained) << x.count.what;
}

// explain_pixel counts each tree's rays by kind, on both sides.
TEST(ErrorCauses, ExplainingAPixelCountsItsTreesRays) {
  Scene s;
  s.materials.push_back(Material{});
  s.lights.push_back({{3, 0, 10}, {1, 1, 1}});  // in front of the sphere, beside the eye
  s.primitives.push_back(make_sphere({0, 0, 0}, 1));
  Traced t(s);
  const Ray r = primary({0, 0, 5}, {0, 0, 0});
  TreeWork work;
  explain_pixel(r, *t.pe, *t.ref, t.tolerance(), traced_pixel(*t.pe, r), traced_pixel(*t.ref, r),
                kTreeRayLimit, &work);
  EXPECT_EQ(work.machine.rays[size_t(RayKind::Primary)], 1u);
  EXPECT_EQ(work.machine.rays[size_t(RayKind::Shadow)], 1u);  // one light
  EXPECT_EQ(work.machine.rays, work.reference.rays);
}

}  // namespace
}  // namespace rtm
