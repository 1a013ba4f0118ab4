// The precision keys on hand-built rays: precision sets every unit, and each unit's own key
// (intersection_precision, dda_precision, shading_precision) changes that unit's arithmetic and
// no other's; hit_refine changes where shading shades and costs refine_cycles.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "geom/test_grid.h"
#include "render/glass_sphere_test_scene.h"
#include "units/intersection.h"
#include "units/search_unit.h"
#include "units/shading_unit.h"

namespace rtm {
namespace {

using test::unit_grid;

struct Pe {
  Scene scene = test::glass_sphere_scene();
  Grid grid;
  PeState pe;
  Pe(const Grid& g, const std::vector<std::string>& sets) : grid(g) {
    pe.config.precision = Precision::Fp64;
    for (const std::string& kv : sets) set_config_assignment(pe.config, kv);
    pe.image = std::make_shared<SceneImage>(scene, grid, pe.config);
  }
};

MachineRay machine_ray(const Vec3& origin, const Vec3& dir) {
  MachineRay r;
  r.ray.origin = origin;
  r.ray.dir = normalize(dir);
  return r;
}

// The walk of docs/numerics.md's corner case: aimed 1e-9 above the corner (1, 1), which float
// cannot resolve (geom/dda_test.cpp, DdaPrecision).
std::vector<std::array<int, 3>> search_walk(const std::vector<std::string>& sets) {
  Pe p(unit_grid({4, 4, 1}), sets);
  SearchUnit unit(p.pe, 0);
  MachineRay r = machine_ray({0.1, 0.1, 0.5}, {0.9, 0.9 + 1e-9, 0});
  std::vector<std::array<int, 3>> cells;
  for (;;) {
    const Work w = unit.take(r, 0);
    cells.push_back(r.examined.cell);
    if (w.out.fifo != FifoId::FeedbackSearch) return cells;
  }
}

/// The hit t the intersection unit finds for a ray at the sphere, in a one-voxel grid round it,
/// with the wide origin latch (the advanced one adds the voxel's entry t to the root unit's).
double intersection_t(std::vector<std::string> sets) {
  sets.insert(sets.begin(), "origin_latch=wide");
  Grid g = unit_grid({1, 1, 1}, {0});
  g.box = {{9, 19, 29}, {11, 21, 31}};
  g.cell = {2, 2, 2};
  Pe p(g, sets);
  MacUnit mac(p.pe, 0);
  RootUnit root(p.pe, 0);
  MacResult m;
  m.r.ray = test::glass_sphere_ray();
  m.r.examined = Dda::start(p.grid, m.r.ray.origin, m.r.ray.dir, 0, kInf);
  m.r.last = true;
  mac.take(m, 0);
  root.take(m, 0);
  EXPECT_EQ(m.r.arrival, MachineRay::Arrival::Hit);
  return m.r.t_hit;
}

struct Shaded {
  std::vector<Ray> rays;
  uint64_t cycles = 0;
};
/// What shading spawns from a hit on the sphere, t 1e-7 beyond the surface (as float rounding
/// leaves it).
Shaded shading(const std::vector<std::string>& sets) {
  Pe p(unit_grid({1, 1, 1}), sets);
  ShadingUnit unit(p.pe);
  MachineRay r;
  r.ray = test::glass_sphere_ray();
  r.arrival = MachineRay::Arrival::Hit;
  r.t_hit = test::glass_sphere_t(r.ray) * (1 + 1e-7);
  PixelSum pixel;
  int32_t id = -1;
  Shaded s;
  s.cycles = unit.take(r, pixel, id, 0).cycles;
  for (size_t k = 1; k < unit.outputs(); ++k) s.rays.push_back(unit.spawn(r, k).ray);
  return s;
}

bool same(const std::vector<Ray>& a, const std::vector<Ray>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].origin != b[i].origin || a[i].dir != b[i].dir ||
        a[i].contribution != b[i].contribution)
      return false;
  return true;
}

TEST(PrecisionKeys, DdaPrecisionChangesTheWalkOnly) {
  const auto fp64 = search_walk({});
  EXPECT_EQ(fp64[1], (std::array<int, 3>{0, 1, 0}));
  EXPECT_NE(search_walk({"dda_precision=fp32"}), fp64);
  EXPECT_NE(search_walk({"precision=fp32"}), fp64);
  EXPECT_EQ(search_walk({"precision=fp32", "dda_precision=fp64"}), fp64);
  EXPECT_EQ(search_walk({"intersection_precision=fp32", "shading_precision=fp32"}), fp64);
}

TEST(PrecisionKeys, IntersectionPrecisionChangesTheRootsOnly) {
  const double fp64 = intersection_t({});
  const double fp32 = intersection_t({"intersection_precision=fp32"});
  EXPECT_NE(fp32, fp64);
  EXPECT_EQ(double(float(fp32)), fp32);  // the root unit's t is a float
  EXPECT_NEAR(fp32, fp64, 1e-5);
  EXPECT_EQ(intersection_t({"precision=fp32"}), fp32);
  EXPECT_EQ(intersection_t({"precision=fp32", "intersection_precision=fp64"}), fp64);
  EXPECT_EQ(intersection_t({"dda_precision=fp32", "shading_precision=fp32"}), fp64);
}

TEST(PrecisionKeys, ShadingPrecisionChangesTheSpawnedRaysOnly) {
  const Shaded fp64 = shading({});
  ASSERT_EQ(fp64.rays.size(), 3u);
  const Shaded fp32 = shading({"shading_precision=fp32"});
  ASSERT_EQ(fp32.rays.size(), 3u);
  EXPECT_FALSE(same(fp32.rays, fp64.rays));
  for (const Ray& r : fp32.rays) EXPECT_EQ(Vec3(glm::vec3(r.dir)), r.dir) << "a float direction";
  EXPECT_TRUE(same(shading({"precision=fp32"}).rays, fp32.rays));
  EXPECT_TRUE(same(shading({"precision=fp32", "shading_precision=fp64"}).rays, fp64.rays));
  EXPECT_TRUE(same(shading({"dda_precision=fp32", "intersection_precision=fp32"}).rays, fp64.rays));
}

TEST(HitRefineKey, NewtonMovesTheHitPointAndCostsRefineCycles) {
  const MachineConfig c;
  const uint64_t plain = uint64_t(c.shade_cycles + 3 * c.spawn_cycles);  // three rays spawned
  const Shaded newton = shading({}), none = shading({"hit_refine=none"});
  EXPECT_EQ(c.hit_refine, HitRefine::Newton);
  EXPECT_EQ(newton.cycles, plain + uint64_t(c.refine_cycles));
  EXPECT_EQ(none.cycles, plain);
  EXPECT_EQ(shading({"refine_cycles=30"}).cycles, plain + 30);
  EXPECT_EQ(shading({"hit_refine=none", "refine_cycles=30"}).cycles, plain);
  // t was 1e-7 off the surface: refined, the spawned rays start elsewhere.
  EXPECT_FALSE(same(newton.rays, none.rays));
}

}  // namespace
}  // namespace rtm
