// Leaving out what a scene does not need (docs/leave-out.md), on the rtm binary: the pruned
// machine (sparse MAC schedule, unused units not elaborated) gives the full machine's image bit
// for bit, says what it left out, and the left-out units are absent from the waveform.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using namespace rtm::test;

const std::string kScenes = std::string(RTM_SOURCE_DIR) + "/scenes/spd/";
const std::string kFull = "--mac-schedule full --set leave_out=false";
const std::string kPruned = "--mac-schedule sparse --set leave_out=true";

struct Case {
  std::string scene, precision;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.scene << " " << c.precision; }
class FullVsPruned : public ::testing::TestWithParam<Case> {};

TEST_P(FullVsPruned, BitIdenticalImagesAndTheSavingsAddUp) {
  Tmp tmp;
  const std::string base =
      kScenes + GetParam().scene + " --size 32x32 --pes 2 --precision " + GetParam().precision;
  const json full = render(tmp, "full", base + " " + kFull);
  const json pruned = render(tmp, "pruned", base + " " + kPruned);
  ASSERT_FALSE(full.is_null() || pruned.is_null());

  const rtm::Image a = rtm::read_image(tmp / "full.exr"), b = rtm::read_image(tmp / "pruned.exr");
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) differ += !(a.rgb[i] == b.rgb[i]);
  EXPECT_EQ(differ, 0u) << "pixels differing between the full and the pruned machine";
  EXPECT_EQ(rtm::read_id_map(tmp / "full-id.exr").ids, rtm::read_id_map(tmp / "pruned-id.exr").ids);
  EXPECT_EQ(full["rays"], pruned["rays"]);
  EXPECT_EQ(full["intersection_tests"], pruned["intersection_tests"]);

  // The full machine runs 28 products a test and saves nothing; the pruned one saves exactly
  // what it skipped, and the cycles it reports saved are cycles of the MAC's entry (the jobs'
  // intervals) it did not spend.
  const auto products = [](const json& j) { return j["mac"]["products"].get<uint64_t>(); };
  EXPECT_EQ(products(full), 28 * full["intersection_tests"].get<uint64_t>());
  EXPECT_EQ(full["left_out"]["mac_products_saved"].get<uint64_t>(), 0u);
  EXPECT_EQ(full["left_out"]["units"].size(), 0u);
  EXPECT_EQ(products(pruned) + pruned["left_out"]["mac_products_saved"].get<uint64_t>(),
            products(full));
  EXPECT_GT(pruned["left_out"]["mac_products_saved"].get<uint64_t>(), 0u);
  EXPECT_EQ(
      full["mac"]["issue_cycles"].get<uint64_t>() - pruned["mac"]["issue_cycles"].get<uint64_t>(),
      pruned["left_out"]["mac_cycles_saved"].get<uint64_t>());
  EXPECT_LT(pruned["cycles"].get<uint64_t>(), full["cycles"].get<uint64_t>());
}

std::vector<Case> all_spd_scenes() {
  std::vector<Case> cases;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(kScenes))
    if (e.path().extension() == ".nff") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  for (const std::string& n : names)
    for (const char* p : {"fp32", "fp64"}) cases.push_back({n, p});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(EverySpdScene, FullVsPruned, ::testing::ValuesIn(all_spd_scenes()),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           std::string n = i.param.scene.substr(0, i.param.scene.find('.')) + "_" +
                                           i.param.precision;
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

/// A matte scene: lights and diffuse spheres, nothing reflects or transmits.
const char* kMatte =
    R"(camera: {eye: [0, 0, 8], look_at: [0, 0, 0], up: [0, 1, 0], fov: 40, resolution: [24, 24]}
lights: [{position: [4, 6, 8]}]
materials:
  m: {diffuse: 0.8, ambient: 0.2}
render: {threshold: 0.01, max_depth: 5}
primitives:
  - {sphere: {center: [-1, 0, 0], radius: 1}, material: m}
  - {sphere: {center: [1.2, 0.3, -0.5], radius: 0.8}, material: m}
)";

TEST(LeaveOut, AMatteSceneHasNoBranchRayUnitsInStatsOrWaveform) {
  Tmp tmp;
  spit(tmp / "matte.yaml", kMatte);
  const json pruned = render(tmp, "pruned", tmp / "matte.yaml --vcd " + (tmp / "pruned.vcd"));
  const json full =
      render(tmp, "full", tmp / "matte.yaml --set leave_out=false --vcd " + (tmp / "full.vcd"));
  ASSERT_FALSE(pruned.is_null() || full.is_null());
  const json& units = pruned["left_out"]["units"];
  EXPECT_NE(std::find(units.begin(), units.end(), "shading.reflection"), units.end());
  EXPECT_NE(std::find(units.begin(), units.end(), "shading.refraction"), units.end());
  EXPECT_EQ(std::find(units.begin(), units.end(), "shading.shadow_rays"), units.end());
  const json& needs = pruned["left_out"]["scene_needs"];
  EXPECT_TRUE(needs["shadow_rays"].get<bool>());
  EXPECT_FALSE(needs["reflected_rays"].get<bool>());
  EXPECT_FALSE(needs["transmitted_rays"].get<bool>());

  const std::string vp = slurp(tmp / "pruned.vcd"), vf = slurp(tmp / "full.vcd");
  EXPECT_NE(vp.find("shadow_rays"), std::string::npos);
  EXPECT_EQ(vp.find("reflection"), std::string::npos) << "a left-out unit is not in the hierarchy";
  EXPECT_EQ(vp.find("refraction"), std::string::npos);
  EXPECT_NE(vf.find("reflection"), std::string::npos) << "the full machine has every unit";
  EXPECT_NE(vf.find("refraction"), std::string::npos);
}

TEST(LeaveOut, AnAmbientOnlySceneHasNoSpawnPathAtAll) {
  Tmp tmp;
  std::string scene = kMatte;
  scene.replace(scene.find("lights: [{position: [4, 6, 8]}]"), 31, "lights: []");
  spit(tmp / "flat.yaml", scene);
  const json pruned = render(tmp, "pruned", tmp / "flat.yaml --vcd " + (tmp / "pruned.vcd"));
  const json full = render(tmp, "full", tmp / "flat.yaml --set leave_out=false");
  ASSERT_FALSE(pruned.is_null() || full.is_null());
  const json& units = pruned["left_out"]["units"];
  for (const char* u :
       {"spawn_fifo", "shading.shadow_rays", "shading.reflection", "shading.refraction"})
    EXPECT_NE(std::find(units.begin(), units.end(), u), units.end()) << u;
  EXPECT_EQ(slurp(tmp / "pruned.vcd").find("spawn_fifo"), std::string::npos);
  EXPECT_EQ(pruned["rays"], full["rays"]);
  EXPECT_EQ(pruned["rays"]["shadow"].get<int>(), 0);
}

}  // namespace
