// The PE's units on their local memory (docs/memory.md, "How the units use it"): any memory
// setting changes timing only, never the image or the ID map; fast and clocked timing agree on
// random memories; a memory-bound machine is named so; a small coefficient RAM misses, and the
// misses cost cycles; the constants the memory now times are refused, naming what replaced them.
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"

namespace rtm::test {
namespace {

using nlohmann::json;

const std::string kScenes = std::string(RTM_SOURCE_DIR) + "/scenes/spd/";
/// Without the host's pre-processing the PEs' work is the frame, so the bottleneck is a PE's.
const std::string kNoHostWork = " --set host_voxel_cycles=0 --set host_ray_cycles=0";

TEST(LocalMemory, NoMemorySettingChangesTheImageOrTheIdMap) {
  Tmp tmp;
  const std::string base =
      kScenes + "balls-1.nff --size 16x16 --pes 2 --set front_buffer_capacity=2";
  ASSERT_FALSE(render(tmp, "ideal", base).is_null());
  const Image ideal = read_image(tmp / "ideal.exr");
  const Image ideal_ids = read_id_map(tmp / "ideal-id.exr");
  std::mt19937 rng(4242);
  uint64_t moved = 0;
  const uint64_t ideal_cycles = render(tmp, "ideal", base)["cycles"].get<uint64_t>();
  for (int i = 0; i < 4; ++i) {
    const std::string args = base + random_memory(rng);
    const std::string name = "m" + std::to_string(i);
    const json j = render(tmp, name, args);
    ASSERT_FALSE(j.is_null()) << args;
    EXPECT_EQ(read_image(tmp / (name + ".exr")).rgb, ideal.rgb) << args;
    EXPECT_EQ(read_id_map(tmp / (name + "-id.exr")).ids, ideal_ids.ids) << args;
    moved += j["cycles"].get<uint64_t>() != ideal_cycles;
  }
  EXPECT_GT(moved, 0u) << "the memories drawn time the frame differently";
}

TEST(LocalMemory, FastAndClockedTimingAgreeOnRandomMemories) {
  Tmp tmp;
  std::mt19937 rng(77);
  const char* scenes[] = {"tree-2.nff", "rings-1.nff", "balls-1.nff"};
  for (int i = 0; i < 3; ++i) {
    const std::string args = kScenes + scenes[i] + " --size 12x12 --pes 2" + random_memory(rng);
    const json fast = render(tmp, "fast", args);
    const json clocked = render(tmp, "clocked", args + " --timing clocked");
    ASSERT_FALSE(fast.is_null() || clocked.is_null()) << args;
    EXPECT_EQ(fast["cycles"], clocked["cycles"]) << args;
    EXPECT_EQ(fast["memory"]["requesters"], clocked["memory"]["requesters"]) << args;
    EXPECT_EQ(fast["per_pe"], clocked["per_pe"]) << args;
    EXPECT_EQ(read_image(tmp / "fast.exr").rgb, read_image(tmp / "clocked.exr").rgb) << args;
  }
}

TEST(LocalMemory, OneSlowPortSharedByFourSearchUnitsIsNamedTheBottleneck) {
  Tmp tmp;
  const std::string args = kScenes + "balls-1.nff --size 32x32 --search-units 4" + kNoHostWork;
  const json ideal = render(tmp, "ideal", args);
  const json slow = render(tmp, "slow", args + " --set memory_ports=1 --set memory_latency=64");
  ASSERT_FALSE(ideal.is_null() || slow.is_null());
  EXPECT_NE(ideal["bottleneck"], "memory") << ideal["bottleneck_reason"];
  EXPECT_EQ(slow["bottleneck"], "memory") << slow["bottleneck_reason"];
  EXPECT_NE(slow["bottleneck_reason"].get<std::string>().find("reads of local memory"),
            std::string::npos);
  EXPECT_GT(slow["cycles"].get<uint64_t>(), ideal["cycles"].get<uint64_t>());
  EXPECT_FALSE(slow["memory"]["ideal"].get<bool>());
  ASSERT_EQ(slow["memory"]["ports"].size(), 1u);
  EXPECT_EQ(slow["memory"]["ports"][0]["busy_cycles"], slow["memory"]["beats"])
      << "one port carries every beat";
  // The search units' requests: one voxel entry of 8 bytes per voxel step.
  uint64_t entries = 0;
  for (int k = 0; k < 4; ++k)
    entries +=
        slow["memory"]["requesters"]["search" + std::to_string(k)]["requests"].get<uint64_t>();
  EXPECT_EQ(entries, slow["summary"]["voxel_steps"].get<uint64_t>());
}

TEST(LocalMemory, ASmallCoefficientRamMissesAndTheMissesCostCycles) {
  Tmp tmp;
  const std::string args = kScenes + "balls-1.nff --size 16x16" + kNoHostWork;
  const json all = render(tmp, "all", args);
  const json small = render(tmp, "small", args + " --set mac_ram_primitives=2");
  ASSERT_FALSE(all.is_null() || small.is_null());
  EXPECT_EQ(all["memory"]["coefficient_ram"]["misses"], 0) << "0: every primitive resident";
  EXPECT_EQ(all["memory"]["coefficient_ram"]["hit_rate"], 1.0);
  const json& ram = small["memory"]["coefficient_ram"];
  EXPECT_GT(ram["misses"].get<uint64_t>(), 0u);
  EXPECT_LT(ram["hit_rate"].get<double>(), 1.0);
  EXPECT_EQ(ram["hits"].get<uint64_t>() + ram["misses"].get<uint64_t>(),
            all["memory"]["coefficient_ram"]["hits"].get<uint64_t>())
      << "one access per primitive tested";
  EXPECT_GT(small["cycles"].get<uint64_t>(), all["cycles"].get<uint64_t>())
      << "each miss loads its record first";
  EXPECT_GT(small["memory"]["requesters"]["lane0"]["bytes"].get<uint64_t>(),
            all["memory"]["requesters"]["lane0"]["bytes"].get<uint64_t>());
  EXPECT_EQ(read_image(tmp / "small.exr").rgb, read_image(tmp / "all.exr").rgb);
}

TEST(LocalMemory, SpillsCostTheTransferOfTheirRecords) {
  Tmp tmp;
  const std::string args = kScenes + "balls-1.nff --size 16x16 --set front_buffer_capacity=1";
  const json wide = render(tmp, "wide", args);
  const json narrow = render(tmp, "narrow", args + " --set memory_bytes_per_cycle=4");
  ASSERT_FALSE(wide.is_null() || narrow.is_null());
  ASSERT_GT(wide["spills"].get<uint64_t>(), 0u);
  // 60 bytes: 4 beats of 16 or 15 of 4, each spill read in the ray's dispatch.
  EXPECT_GT(narrow["cycles"].get<uint64_t>(), wide["cycles"].get<uint64_t>());
  EXPECT_GE(wide["memory"]["requesters"]["front_buffer"]["bytes"].get<uint64_t>(),
            256 * 28 + wide["spills"].get<uint64_t>() * 60)
      << "every primary ray read, every spilled ray read back";
  EXPECT_EQ(read_image(tmp / "narrow.exr").rgb, read_image(tmp / "wide.exr").rgb);
}

TEST(LocalMemory, TheConstantsItNowTimesAreRefusedNamingTheirReplacement) {
  Tmp tmp;
  for (const char* key : {"voxel_read_cycles", "coef_load_cycles", "spill_cycles"}) {
    const Proc r = run_rtm(std::string("render --size 4x4 --set ") + key + "=2 -q", tmp);
    EXPECT_EQ(r.exit_code, 2) << key << ": " << r.err;
    EXPECT_NE(r.err.find(std::string(key) + ": no longer a key"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("local memory's time"), std::string::npos) << r.err;
  }
}

// The host's writes go through the PE's memory in bursts as they arrive (units/pe_memory.h): rays
// streaming in while the units work contend with them for one port; the gather is one counted read.
TEST(LocalMemory, TheHostsWritesComeInBurstsAndContendWithTheUnits) {
  Tmp tmp;
  constexpr uint64_t kBurst = 64, kRay = 28, kPixel = 16, kBlock = 8, kPixels = 16 * 16;
  const std::string args =
      kScenes + "balls-1.nff --size 16x16 --set ray_block=8 --set link_bandwidth_mb_s=10000" +
      kNoHostWork;
  const json ideal = render(tmp, "ideal", args);
  const json one =
      render(tmp, "one", args + " --set memory_ports=1 --set memory_bytes_per_cycle=1");
  ASSERT_FALSE(ideal.is_null() || one.is_null());
  const uint64_t scene = one["host"]["scene_bytes"].get<uint64_t>();
  const uint64_t bursts =
      (scene + kBurst - 1) / kBurst + kPixels / kBlock * ((kBlock * kRay + kBurst - 1) / kBurst);
  for (const json* j : {&ideal, &one}) {
    const json& host = (*j)["memory"]["requesters"]["host"];
    EXPECT_EQ(host["requests"].get<uint64_t>(), bursts + 1) << "every burst, and the gather's read";
    EXPECT_EQ(host["bytes"].get<uint64_t>(), scene + kPixels * (kRay + kPixel));
  }
  EXPECT_EQ(ideal["memory"]["requesters"]["host"]["stall_cycles"], 0);
  EXPECT_GT(one["memory"]["requesters"]["host"]["stall_cycles"].get<uint64_t>(), 0u)
      << "a burst waited for the units' reads";
  EXPECT_EQ(one["memory"]["ports"][0]["busy_cycles"], one["memory"]["beats"])
      << "the port carried the host's bursts too";
  EXPECT_EQ(read_image(tmp / "one.exr").rgb, read_image(tmp / "ideal.exr").rgb);
}

}  // namespace
}  // namespace rtm::test
