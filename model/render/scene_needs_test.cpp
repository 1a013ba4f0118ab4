#include "render/scene_needs.h"

#include <gtest/gtest.h>

#include "render/voxel_test.h"

namespace rtm {
namespace {

/// A one-sphere scene (plus whatever `extra` adds) in the native format.
Scene scene_with(const std::string& materials, const std::string& lights, const std::string& render,
                 const std::string& extra_primitives = "") {
  const std::string text =
      "camera: {eye: [0, 0, 10], look_at: [0, 0, 0], up: [0, 1, 0], fov: 40, resolution: [8, "
      "8]}\n" +
      lights + "materials:\n" + materials + "render: " + render +
      "\nprimitives:\n  - {sphere: {center: [0, 0, 0], radius: 1}, material: m}\n" +
      extra_primitives;
  return parse_native(text, "needs.yaml");
}

SceneNeeds needs_of(const Scene& s) {
  const Grid g = build_grid(s.primitives, s.grid);
  const SceneMemory<float> mem(s, g);
  return analyse_scene(s, mem.rams);
}

const std::string kOneLight = "lights: [{position: [5, 5, 5]}]\n";

TEST(SceneNeeds, MatteSceneSpawnsOnlyShadowRays) {
  const SceneNeeds n =
      needs_of(scene_with("  m: {diffuse: 0.8}\n", kOneLight, "{threshold: 0.01, max_depth: 5}"));
  EXPECT_TRUE(n.shadow_rays);
  EXPECT_FALSE(n.reflected_rays);
  EXPECT_FALSE(n.transmitted_rays);
  EXPECT_EQ(n.deepest_generation, 1);
  EXPECT_TRUE(n.spawns_rays());
}

TEST(SceneNeeds, NoLightsNoShadowRays) {
  const SceneNeeds n =
      needs_of(scene_with("  m: {diffuse: 0.8}\n", "", "{threshold: 0.01, max_depth: 5}"));
  EXPECT_FALSE(n.shadow_rays);
  EXPECT_FALSE(n.spawns_rays());
}

TEST(SceneNeeds, NoDiffuseNoShadowRays) {
  const SceneNeeds n = needs_of(
      scene_with("  m: {diffuse: 0, ambient: 1}\n", kOneLight, "{threshold: 0.01, max_depth: 5}"));
  EXPECT_FALSE(n.shadow_rays);
}

TEST(SceneNeeds, BranchRaysOnlyAboveTheThreshold) {
  // ks = 0.5 passes a 0.3 threshold once (generation 2 carries 0.5), generation 3 would carry 0.25.
  SceneNeeds n =
      needs_of(scene_with("  m: {specular: 0.5}\n", kOneLight, "{threshold: 0.3, max_depth: 5}"));
  EXPECT_TRUE(n.reflected_rays);
  EXPECT_FALSE(n.transmitted_rays);
  EXPECT_EQ(n.deepest_generation, 2);
  // At or below the threshold a branch ray is dropped, so it is never spawned.
  n = needs_of(scene_with("  m: {specular: 0.3, transmission: 0.2}\n", kOneLight,
                          "{threshold: 0.3, max_depth: 5}"));
  EXPECT_FALSE(n.reflected_rays);
  EXPECT_FALSE(n.transmitted_rays);
  EXPECT_EQ(n.deepest_generation, 1);
  // max_depth 1: primary rays only, whatever the materials.
  n = needs_of(scene_with("  m: {specular: 0.9, transmission: 0.9}\n", kOneLight,
                          "{threshold: 0, max_depth: 1}"));
  EXPECT_FALSE(n.reflected_rays);
  EXPECT_FALSE(n.transmitted_rays);
}

TEST(SceneNeeds, DeepestGenerationFollowsTheLargestCoefficient) {
  // kt = 0.9, threshold 0.5: 0.9, 0.81, 0.729, 0.6561, 0.59049 pass, 0.531441 passes, 0.4783 not.
  const SceneNeeds n = needs_of(scene_with("  m: {specular: 0.2, transmission: 0.9}\n", kOneLight,
                                           "{threshold: 0.5, max_depth: 20}"));
  EXPECT_TRUE(n.transmitted_rays);
  EXPECT_FALSE(n.reflected_rays);
  EXPECT_EQ(n.deepest_generation, 7);
}

TEST(SceneNeeds, UnusedMaterialsDoNotCount) {
  const SceneNeeds n =
      needs_of(scene_with("  m: {diffuse: 0.8}\n  unused: {specular: 0.9, transmission: 0.9}\n",
                          kOneLight, "{threshold: 0.01, max_depth: 5}"));
  EXPECT_FALSE(n.reflected_rays);
  EXPECT_FALSE(n.transmitted_rays);
}

TEST(SceneNeeds, SparseProductsPerPrimitive) {
  const Scene s = scene_with(
      "  m: {diffuse: 0.8}\n", kOneLight, "{threshold: 0.01, max_depth: 5}",
      "  - {polygon: {vertices: [[-1, -1, -2], [1, -1, -2], [0, 1, -2]]}, material: m}\n");
  const SceneNeeds n = needs_of(s);
  ASSERT_EQ(n.mac_ops.size(), 2u);
  // A re-centred sphere: A, B, C (α), 2A, 2B, 2C (β), A, B, C, J (γ).
  EXPECT_EQ(n.mac_ops[0].size(), 10u);
  // The triangle's plane z = -2, re-centred to z = 0: I Uz (β) and I Vz (γ); J is zero.
  EXPECT_EQ(n.mac_ops[1].size(), 2u);
  EXPECT_EQ(n.products_full, 56u);
  EXPECT_EQ(n.products_sparse, 12u);
  // Every kept product has a non-zero word, every dropped one a zero word.
  const Grid g = build_grid(s.primitives, s.grid);
  const SceneMemory<float> mem(s, g);
  for (size_t p = 0; p < 2; ++p) {
    size_t next = 0;
    for (size_t k = 0; k < kMacSchedule.size(); ++k) {
      const bool kept = next < n.mac_ops[p].size() && n.mac_ops[p][next] == k;
      EXPECT_EQ(kept, mem.rams[p][kMacSchedule[k].w] != 0) << "primitive " << p << " product " << k;
      next += kept;
    }
  }
  EXPECT_EQ(n.clipped_primitives, 1);
  EXPECT_FALSE(n.clipped[0]);
  EXPECT_TRUE(n.clipped[1]);
}

TEST(SceneNeeds, TheRamPrecisionDecidesWhatIsZero) {
  // A linear coefficient below float's range is a zero word in a float32 RAM, not in fp64.
  Scene s = scene_with("  m: {diffuse: 0.8}\n", kOneLight, "{threshold: 0.01, max_depth: 5}");
  CoefRam<double> wide = load_ram<double>(s.primitives[0].q);
  wide[kRamG] = 1e-60;
  CoefRam<float> narrow = load_ram<float>(s.primitives[0].q);
  narrow[kRamG] = float(1e-60);
  const SceneNeeds n64 = analyse_scene(s, std::vector<CoefRam<double>>{wide});
  const SceneNeeds n32 = analyse_scene(s, std::vector<CoefRam<float>>{narrow});
  EXPECT_EQ(n64.products_sparse, n32.products_sparse + 2);  // G Ux in β, G Vx in γ
}

TEST(SceneNeeds, GridIsTheScenesOwnElseTheAutomaticResolution) {
  const std::string m = "  m: {diffuse: 0.8}\n";
  EXPECT_EQ(needs_of(scene_with(m, kOneLight, "{max_depth: 5, grid: [3, 4, 5]}")).grid,
            (std::array<int, 3>{3, 4, 5}));
  const Scene s = scene_with(m, kOneLight, "{max_depth: 5}");
  EXPECT_EQ(needs_of(s).grid, build_grid(s.primitives, s.grid).n);
}

}  // namespace
}  // namespace rtm
