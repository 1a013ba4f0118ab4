// partition = dynamic in whole renders (docs/machine.md, "Screen partitioning"): tiles handed to
// the PEs as they ask move only times, so the picture, the ID map and the ray counts are those of
// a static partition; the host deals every tile once; the link carries the requests and
// descriptors; the modules in clocked timing give the fast timing's cycles.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"

using nlohmann::json;
using namespace rtm::test;

namespace {

const std::string kScene = std::string(RTM_SOURCE_DIR) + "/scenes/spd/balls-1.nff";
constexpr int kWidth = 13, kHeight = 11;
const std::string kFrame =
    kScene + " --size " + std::to_string(kWidth) + "x" + std::to_string(kHeight);

int tiles_of(int edge) { return ((kWidth + edge - 1) / edge) * ((kHeight + edge - 1) / edge); }

struct Case {
  const char* name;
  int pes, tile;
  std::string more;
};

TEST(DynamicPartition, GivesTheStaticPictureIdsAndRaysDealingEveryTileOnce) {
  Tmp tmp;
  const json fixed = render(tmp, "static", kFrame + " --pes 3 --partition scanlines");
  ASSERT_FALSE(fixed.is_null());
  const auto rgb = rtm::read_image(tmp / "static.exr").rgb;
  const auto ids = rtm::read_id_map(tmp / "static-id.exr").ids;
  const std::vector<Case> cases = {
      {"one-pe", 1, 4, ""},
      {"tiles-not-dividing", 3, 5, ""},
      {"more-pes-than-tiles", 7, 8, ""},
      // Every pixel its own tile: a request per pixel, PEs finishing while the last are dealt.
      {"pixel-tiles", 4, 1, ""},
      {"pe-rays-tree-streamed", 5, 3,
       " --set ray_generation=pe --set link_topology=tree --set broadcast=true --set "
       "gather=streamed --set voxelisation=pe"},
      {"star-as-finished", 4, 6,
       " --set link_topology=star --set host_ports=2 --set gather=as_finished"},
      {"clocked-after-all", 3, 4, " --timing clocked"},
  };
  for (const Case& c : cases) {
    const json j = render(tmp, c.name,
                          kFrame + " --pes " + std::to_string(c.pes) +
                              " --partition dynamic --set tile=" + std::to_string(c.tile) + c.more);
    ASSERT_FALSE(j.is_null()) << c.name;
    EXPECT_EQ(rtm::read_image(tmp / (std::string(c.name) + ".exr")).rgb, rgb) << c.name;
    EXPECT_EQ(rtm::read_id_map(tmp / (std::string(c.name) + "-id.exr")).ids, ids) << c.name;
    EXPECT_EQ(j["rays"], fixed["rays"]) << c.name;
    EXPECT_EQ(j["partition"], "dynamic");
    // Every tile dealt, to one PE each; each PE got one up front while any were left.
    const int tiles = tiles_of(c.tile);
    int dealt = 0, without = 0, least = tiles, most = 0;
    for (const json& pe : j["per_pe"]) {
      const int t = pe["tiles"];
      dealt += t;
      without += t == 0;
      least = std::min(least, t);
      most = std::max(most, t);
      EXPECT_EQ(t > 0, pe["rays"].get<uint64_t>() > 0) << c.name;
    }
    EXPECT_EQ(dealt, tiles) << c.name;
    EXPECT_EQ(without, std::max(0, c.pes - tiles)) << c.name;
    EXPECT_EQ(j["tiles_per_pe"]["min"], least) << c.name;
    EXPECT_EQ(j["tiles_per_pe"]["max"], most) << c.name;
    EXPECT_DOUBLE_EQ(j["tiles_per_pe"]["mean"].get<double>(), double(tiles) / c.pes) << c.name;
  }
  EXPECT_TRUE(fixed["tiles_per_pe"].is_null());
  EXPECT_EQ(fixed["per_pe"][0]["tiles"], 0);
}

// On one serial link, rays made on the PEs (docs/machine.md, "Screen partitioning"): the scene
// once (a broadcast), each PE's first tile as the camera record and a descriptor (64 + 8 bytes),
// every later tile and the final "none" as a request and a descriptor (4 + 8), a PE without a
// tile the "none" alone; the frame buffers, 16 bytes a pixel.
TEST(DynamicPartition, TheLinkCarriesTheRequestsAndDescriptors) {
  Tmp tmp;
  for (const int pes : {3, 8}) {
    const json j = render(tmp, "serial",
                          kFrame + " --pes " + std::to_string(pes) +
                              " --partition dynamic --set tile=4 --set ray_generation=pe "
                              "--set broadcast=true --set link_topology=serial");
    ASSERT_FALSE(j.is_null());
    uint64_t bytes = j["host"]["scene_bytes"].get<uint64_t>() + uint64_t(kWidth * kHeight) * 16;
    for (const json& pe : j["per_pe"]) {
      const uint64_t t = pe["tiles"];
      bytes += t > 0 ? 64 + 8 + 12 * t : 8;
    }
    EXPECT_EQ(j["interconnect"]["bytes"].get<uint64_t>(), bytes) << pes << " PEs";
  }
}

// The PEs on the engine and as modules in clocked timing: the same cycles, PE by PE.
TEST(DynamicPartition, ClockedTimingGivesTheFastCycles) {
  Tmp tmp;
  const std::string args = kFrame +
                           " --pes 4 --partition dynamic --set tile=3 --set link_topology=tree "
                           "--set ray_generation=pe --set gather=as_finished";
  const json fast = render(tmp, "fast", args);
  const json clocked = render(tmp, "clocked", args + " --timing clocked");
  ASSERT_FALSE(fast.is_null() || clocked.is_null());
  EXPECT_TRUE(fast["pe_simulation"]["engine"].get<bool>());
  EXPECT_EQ(clocked["cycles"], fast["cycles"]);
  EXPECT_EQ(clocked["host"], fast["host"]);
  EXPECT_EQ(clocked["per_pe"], fast["per_pe"]);
}

TEST(DynamicPartition, StreamedRaysAreRefused) {
  Tmp tmp;
  const Proc r = run_rtm(
      "render " + kFrame + " --partition dynamic --set ray_block=10 -q --out " + (tmp / "x.exr"),
      tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("ray_block"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("dynamic"), std::string::npos) << r.err;
}

}  // namespace
