// `rtm render --error-map` and the statistics' error.causes, on a frame where the float32 paper
// machine differs from the reference in many ways (scenes/stiff/far-origin.yaml without
// re-centring): every differing pixel has one cause, the map and the statistics say the same, and
// an fp64 machine has nothing to explain.
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"

namespace {

using namespace rtm::test;
using nlohmann::json;

const std::string kFarOrigin = std::string(RTM_SOURCE_DIR) + "/scenes/stiff/far-origin.yaml";
// The paper's arithmetic in world coordinates: in the grid's frame the far-origin frame has
// nothing to explain (docs/numerics.md, "Where the scene is").
const std::string kPaper =
    " --set recentre=false --set coef_scaling=none --set origin_latch=machine --set pe_frame=world";

/// The channel named `name` of an error map, per pixel.
std::vector<float> channel(const rtm::Channels& c, const std::string& name) {
  std::vector<float> v;
  for (size_t k = 0; k < c.names.size(); ++k)
    if (c.names[k] == name)
      for (size_t i = k; i < c.values.size(); i += c.names.size()) v.push_back(c.values[i]);
  EXPECT_EQ(v.size(), size_t(c.width) * size_t(c.height)) << "channel " << name;
  return v;
}

TEST(ErrorMap, EveryDifferingPixelHasOneCauseAndTheMapAgreesWithTheStatistics) {
  Tmp tmp;
  const json j = render(tmp, "paper", kFarOrigin + kPaper + " --error-map " + (tmp / "why.exr"));
  ASSERT_FALSE(j.is_null());
  const json& causes = j["error"]["causes"];
  const uint64_t differing = j["error"]["pixels_over_1_255"];
  ASSERT_GT(differing, 1000u);  // measured 1505 of 4096
  EXPECT_EQ(causes["pixels"], differing);
  uint64_t sum = 0, partings = 0;
  for (const auto& [name, n] : causes["by_cause"].items()) sum += n.get<uint64_t>();
  for (const json& p : causes["partings"]) partings += p["pixels"].get<uint64_t>();
  EXPECT_EQ(sum, differing);
  EXPECT_EQ(partings, differing);
  EXPECT_EQ(causes["by_cause"]["unknown"], 0)
      << "every tree traced again sums to its image's pixel";
  // This frame parts in many ways: hits lost and gained, other primitives, shadows both ways.
  for (const char* c : {"missed", "extra_hit", "other_primitive", "shadow_blocked",
                        "shadow_unblocked", "hit_point"})
    EXPECT_GT(causes["by_cause"][c].get<uint64_t>(), 0u) << c;

  const rtm::Channels map = rtm::read_channels(tmp / "why.exr");
  ASSERT_EQ(map.width, 64);
  ASSERT_EQ(map.height, 64);
  const std::vector<float> cause = channel(map, "cause"), generation = channel(map, "generation"),
                           kind = channel(map, "kind");
  std::map<int, uint64_t> by_code;
  uint64_t marked = 0;
  for (size_t i = 0; i < cause.size(); ++i) {
    if (cause[i] == 0) {
      EXPECT_EQ(generation[i], 0);
      EXPECT_EQ(kind[i], -1);
      continue;
    }
    ++marked;
    ++by_code[int(cause[i])];
    EXPECT_GE(generation[i], 1);
    EXPECT_GE(kind[i], 0);
  }
  EXPECT_EQ(marked, differing);
  // Codes in ErrorCause's order: none, missed, extra_hit, other_primitive, shadow_blocked, ...
  EXPECT_EQ(by_code[1], causes["by_cause"]["missed"].get<uint64_t>());
  EXPECT_EQ(by_code[4], causes["by_cause"]["shadow_blocked"].get<uint64_t>());
  const rtm::Image picture = rtm::read_image(tmp / "why.png");
  EXPECT_EQ(picture.width, 64);
}

TEST(ErrorMap, TheSummarySaysWhyThePixelsDiffer) {
  Tmp tmp;
  const Proc r = run_rtm("render " + kFarOrigin + kPaper + " --out " + (tmp / "a.png"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const size_t at = r.out.find("\nwhy they differ (first ray to part from the reference): ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string line = r.out.substr(at + 1, r.out.find('\n', at + 1) - at - 1);
  EXPECT_NE(line.find(" other_primitive (most at generation 1, primary)"), std::string::npos)
      << line;
  EXPECT_NE(line.find(" shadow_blocked (most at generation 2, shadow)"), std::string::npos) << line;
  EXPECT_NE(r.out.find(" s explaining the differing pixels"), std::string::npos) << r.out;
  // A frame with nothing to explain has no such line.
  const Proc exact =
      run_rtm("render " + kFarOrigin + kPaper + " --precision fp64 --out " + (tmp / "b.png"), tmp);
  ASSERT_EQ(exact.exit_code, 0) << exact.err;
  EXPECT_EQ(exact.out.find("why they differ"), std::string::npos) << exact.out;
}

TEST(ErrorMap, AnFp64MachineHasNothingToExplain) {
  Tmp tmp;
  const json j = render(tmp, "fp64",
                        kFarOrigin + kPaper + " --precision fp64 --error-map " + (tmp / "why.exr"));
  ASSERT_FALSE(j.is_null());
  EXPECT_EQ(j["error"]["pixels_over_1_255"], 0);
  EXPECT_EQ(j["error"]["causes"]["pixels"], 0);
  EXPECT_TRUE(j["error"]["causes"]["partings"].empty());
  for (float c : channel(rtm::read_channels(tmp / "why.exr"), "cause")) ASSERT_EQ(c, 0);
}

TEST(ErrorMap, ABadErrorMapIsABadCommandLine) {
  Tmp tmp;
  const Proc png = run_rtm(
      "render --size 8x8 -q --out " + (tmp / "a.png") + " --error-map " + (tmp / "why.png"), tmp);
  EXPECT_EQ(png.exit_code, 2);
  EXPECT_NE(png.err.find("--error-map"), std::string::npos) << png.err;
  EXPECT_NE(png.err.find(".exr"), std::string::npos) << png.err;
  const Proc ref = run_rtm("render --reference --size 8x8 -q --out " + (tmp / "a.png") +
                               " --error-map " + (tmp / "w.exr"),
                           tmp);
  EXPECT_EQ(ref.exit_code, 2);
  EXPECT_NE(ref.err.find("--reference"), std::string::npos) << ref.err;
}

}  // namespace
