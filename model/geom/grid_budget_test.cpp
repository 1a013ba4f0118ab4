// The reference renderer's grid: the reference budget of the resolution rule, the exact sphere
// test and the threaded build (geom/grid.h).
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "geom/grid.h"
#include "geom/test_random.h"

namespace rtm {
namespace {

GridOptions cpu_options() {
  GridOptions o;
  size_for_cpu(o);
  return o;
}

/// `big` spheres of radius r among 3000 tiny ones in a dense cluster, which sets a fine voxel edge
/// that the big ones cross everywhere.
std::vector<Primitive> big_and_tiny(std::mt19937& rng, int big, double r) {
  std::vector<Primitive> prims;
  for (int i = 0; i < big; ++i)
    prims.push_back(make_sphere(
        {test::uniform(rng, -8, 8), test::uniform(rng, -8, 8), test::uniform(rng, -8, 8)}, r));
  for (int i = 0; i < 3000; ++i)
    prims.push_back(make_sphere(
        {test::uniform(rng, -2, 2), test::uniform(rng, -2, 2), test::uniform(rng, -2, 2)}, 0.02));
  return prims;
}

TEST(GridBudget, AFewHugeSpheresAmongManyTinyOnes) {
  // Four huge spheres: their references are of the order of the grid's voxels, which the build
  // pays for anyway, so the density rule's grid is kept.
  std::mt19937 rng(5);
  const std::vector<Primitive> prims = big_and_tiny(rng, 4, 30);
  const GridOptions cpu = cpu_options();
  const Grid g = build_grid(prims, cpu);
  EXPECT_EQ(g.n, density_resolution(prims, g.box, cpu));
  EXPECT_LE(double(g.items.size()), 2.0 * double(g.voxel_count()));
  size_t huge = 0;  // the four huge spheres are primitives 0 to 3
  for (uint32_t id : g.items) huge += id < 4;
  EXPECT_GT(huge, g.items.size() / 2);
  std::printf("4 huge and 3000 tiny: %dx%dx%d, %zu references\n", g.n[0], g.n[1], g.n[2],
              g.items.size());
}

TEST(GridBudget, ManyLargeSpheresKeepTheReferencesInProportion) {
  // 800 overlapping spheres of radius 6 (SPD shells' trouble): the density rule's grid would
  // hold far more references than the budget and than twice its voxels.
  std::mt19937 rng(6);
  const std::vector<Primitive> prims = big_and_tiny(rng, 800, 6);
  const GridOptions cpu = cpu_options();
  const Grid kept = build_grid(prims, cpu);
  const double budget = cpu.max_refs_per_primitive * double(prims.size());
  const std::array<int, 3> fine = density_resolution(prims, kept.box, cpu);
  const double fine_refs = estimated_references(prims, kept.box, fine);
  const double fine_voxels = double(fine[0]) * fine[1] * fine[2];
  EXPECT_GT(fine_refs, 4 * budget);
  EXPECT_GT(fine_refs, 2 * fine_voxels);
  // The kept grid is within the budget, and coarser only as much as it must be.
  EXPECT_LE(double(kept.items.size()), budget);
  EXPECT_GT(double(kept.items.size()), 0.5 * budget);
  EXPECT_LT(double(kept.voxel_count()), fine_voxels);
  // The estimate the rule uses is within a factor of two of the real count.
  const double est = estimated_references(prims, kept.box, kept.n);
  EXPECT_GT(est, 0.5 * double(kept.items.size()));
  EXPECT_LT(est, 2.0 * double(kept.items.size()));
  std::printf(
      "800 large and 3000 tiny: density rule %dx%dx%d, %.0f references estimated; budget %.0f: "
      "%dx%dx%d, %zu "
      "references (estimated %.0f)\n",
      fine[0], fine[1], fine[2], fine_refs, budget, kept.n[0], kept.n[1], kept.n[2],
      kept.items.size(), est);
}

TEST(GridBudget, SmallPrimitivesKeepTheDensityRule) {
  std::mt19937 rng(6);
  std::vector<Primitive> prims;
  for (int i = 0; i < 2000; ++i)
    prims.push_back(make_sphere(
        {test::uniform(rng, -10, 10), test::uniform(rng, -10, 10), test::uniform(rng, -10, 10)},
        0.1));
  const GridOptions cpu = cpu_options();
  Aabb box;
  for (const Primitive& p : prims) box.extend(p.bounds);
  EXPECT_EQ(scene_resolution(prims, box, cpu), density_resolution(prims, box, cpu));
  // The machine's options have no budget: its grids are the density rule's, as before.
  const GridOptions machine;
  EXPECT_EQ(machine.max_refs_per_primitive, 0);
  EXPECT_FALSE(machine.exact_spheres);
}

/// Brute force in long double: does the padded voxel's box meet the sphere's surface?
bool exact_touch(const Grid& g, int x, int y, int z, const Primitive& p) {
  const int v[3] = {x, y, z};
  long double near2 = 0, far2 = 0;
  for (int a = 0; a < 3; ++a) {
    const long double lo = (long double)g.plane(a, v[a]) - 1e-3L * g.cell[a] - p.p0[a];
    const long double hi = (long double)g.plane(a, v[a] + 1) + 1e-3L * g.cell[a] - p.p0[a];
    const long double n = lo > 0 ? lo : (hi < 0 ? -hi : 0);
    near2 += n * n;
    far2 += std::max(lo * lo, hi * hi);
  }
  const long double r2 = (long double)p.r0 * p.r0;
  return near2 <= r2 && far2 >= r2;
}

TEST(GridBudget, ReferencesEqualABruteForceExactOverlap) {
  std::mt19937 rng(9);
  for (int scene = 0; scene < 6; ++scene) {
    SCOPED_TRACE(scene);
    std::vector<Primitive> prims;
    const int n = 20 + int(rng() % 400);
    for (int i = 0; i < n; ++i) {
      const double r =
          test::log_uniform(rng, -2, 0.5);  // before the centre (test_random.h says why)
      prims.push_back(make_sphere(
          {test::uniform(rng, -5, 5), test::uniform(rng, -5, 5), test::uniform(rng, -5, 5)}, r));
    }
    GridOptions opt = cpu_options();
    const Grid g = build_grid(prims, opt, 1);
    std::set<std::pair<int64_t, uint32_t>> built, brute;
    for (int64_t v = 0; v < g.voxel_count(); ++v)
      for (uint32_t k = g.start[size_t(v)]; k < g.start[size_t(v) + 1]; ++k)
        built.insert({v, g.items[k]});
    for (int z = 0; z < g.n[2]; ++z)
      for (int y = 0; y < g.n[1]; ++y)
        for (int x = 0; x < g.n[0]; ++x)
          for (uint32_t id = 0; id < prims.size(); ++id)
            if (exact_touch(g, x, y, z, prims[id])) brute.insert({g.index(x, y, z), id});
    EXPECT_EQ(built, brute);
    // The interval bound the machine uses is conservative: it lists every voxel the exact test
    // does.
    opt.exact_spheres = false;
    opt.resolution = g.n;
    const Grid bound = build_grid(prims, opt, 1);
    size_t missing = 0;
    for (const auto& [v, id] : built) {
      bool listed = false;
      for (uint32_t k = bound.start[size_t(v)]; k < bound.start[size_t(v) + 1]; ++k)
        listed = listed || bound.items[k] == id;
      missing += !listed;
    }
    EXPECT_EQ(missing, 0u);
  }
}

TEST(GridBudget, ThreadsGiveTheSameGrid) {
  std::mt19937 rng(10);
  std::vector<Primitive> prims;
  for (int i = 0; i < 900; ++i) {
    const double r = test::log_uniform(rng, -1, 0.7);  // before the centre (test_random.h says why)
    prims.push_back(make_sphere(
        {test::uniform(rng, -40, 40), test::uniform(rng, -40, 40), test::uniform(rng, -40, 40)},
        r));
  }
  for (int i = 0; i < 300; ++i) {
    const Vec3 b{test::uniform(rng, -40, 40), test::uniform(rng, -40, 40),
                 test::uniform(rng, -40, 40)};
    prims.push_back(make_cone(b, 0.5, b + test::random_unit(rng) * 5.0, 0.2));
  }
  for (bool exact : {false, true}) {
    GridOptions opt = cpu_options();
    opt.exact_spheres = exact;
    const Grid one = build_grid(prims, opt, 1);
    for (int threads : {2, 3, 7}) {
      const Grid many = build_grid(prims, opt, threads);
      EXPECT_EQ(many.n, one.n);
      EXPECT_EQ(many.start, one.start);
      EXPECT_EQ(many.items, one.items);
    }
  }
}

}  // namespace
}  // namespace rtm
