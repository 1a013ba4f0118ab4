// The PE engine against the modules it stands in for: the same frame rendered both ways must
// give the same event log (every unit's every take and put, in cycles), picture, ID map and
// every statistic (cycles, per-PE and per-unit counters, FIFO peaks and means, host phases), over
// configurations that exercise each of its paths. docs/machine.md, "The PE engine";
// docs/architecture.md, "The event log".
#include <random>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"

using nlohmann::json;
using namespace rtm::test;

namespace {

const std::string kScenes = std::string(RTM_SOURCE_DIR) + "/scenes/spd/";

/// The stats without what may differ between two runs of the same frame: wall times (every
/// `*_seconds`), the reference cache and how the PEs were simulated (the configuration and the
/// command line that chose it).
json comparable(json j) {
  for (const char* key : {"reference", "pe_simulation", "config", "command_line"}) j.erase(key);
  for (auto it = j.begin(); it != j.end();) {
    const std::string key = it.key();
    if (key.size() >= 7 && key.compare(key.size() - 7, 7, "seconds") == 0) {
      it = j.erase(it);
      continue;
    }
    if (it->is_object()) *it = comparable(*it);
    ++it;
  }
  return j;
}

/// The first line where two event logs part ("" when they are the same), each named, e.g.
/// "line 1234: modules '215703 pe0 search ray17 put intersect_fifo', engine '... put
/// feedback_search'".
std::string first_difference(const std::string& modules_log, const std::string& engine_log,
                             const std::string& first = "modules",
                             const std::string& second = "engine") {
  std::istringstream m(modules_log), e(engine_log);
  std::string a, b;
  for (int line = 1;; ++line) {
    const bool more_m = bool(std::getline(m, a)), more_e = bool(std::getline(e, b));
    if (!more_m && !more_e) return "";
    if (!more_m) a = "(log ended)";
    if (!more_e) b = "(log ended)";
    if (a != b)
      return "line " + std::to_string(line) + ": " + first + " '" + a + "', " + second + " '" + b +
             "'";
  }
}

/// Renders the frame `args` names twice, with `a` and then `b` added, and expects the same event
/// log, picture, ID map and statistics; returns both runs' statistics.
std::pair<json, json> expect_same_frame(const std::string& args, const std::string& a,
                                        const std::string& b) {
  Tmp tmp;
  const json ja = render(tmp, "a", args + " " + a + " --event-log " + (tmp / "a.log"));
  const json jb = render(tmp, "b", args + " " + b + " --event-log " + (tmp / "b.log"));
  if (ja.is_null() || jb.is_null()) {
    ADD_FAILURE() << "a render failed: " << args;
    return {ja, jb};
  }
  EXPECT_GT(jb["cycles"].get<uint64_t>(), 0u);
  const std::string log = slurp(tmp / "a.log");
  EXPECT_NE(log.find(" take "), std::string::npos) << "an empty event log compares nothing";
  EXPECT_EQ(first_difference(log, slurp(tmp / "b.log"), a.empty() ? "default" : a,
                             b.empty() ? "default" : b),
            "")
      << "the event logs part; " << args;
  const json ca = comparable(ja), cb = comparable(jb);
  for (auto& [key, value] : ca.items()) EXPECT_EQ(value, cb[key]) << key << " differs; " << args;
  EXPECT_EQ(ca.size(), cb.size());
  EXPECT_EQ(rtm::read_image(tmp / "a.exr").rgb, rtm::read_image(tmp / "b.exr").rgb) << args;
  EXPECT_EQ(rtm::read_id_map(tmp / "a-id.exr").ids, rtm::read_id_map(tmp / "b-id.exr").ids) << args;
  return {ja, jb};
}

void expect_engine_matches_modules(const std::string& args) {
  const auto [modules, engine] = expect_same_frame(args, "--set pe_simulation=modules", "");
  if (modules.is_null() || engine.is_null()) return;
  EXPECT_TRUE(engine["pe_simulation"]["engine"].get<bool>()) << engine["pe_simulation"];
  EXPECT_FALSE(modules["pe_simulation"]["engine"].get<bool>());
}

struct Case {
  const char* name;
  const char* args;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }
class EngineMatchesModules : public ::testing::TestWithParam<Case> {};

TEST_P(EngineMatchesModules, SamePictureAndStatistics) {
  expect_engine_matches_modules(kScenes + GetParam().args);
}

INSTANTIATE_TEST_SUITE_P(
    Paths, EngineMatchesModules,
    ::testing::Values(
        Case{"OnePe", "balls-1.nff --size 32x32"},
        Case{"BlocksOnThreePes", "rings-1.nff --size 48x48 --pes 3 --partition blocks"},
        // Primary rays arriving block by block while the PEs work.
        Case{"StreamedRays", "tree-2.nff --size 32x32 --pes 2 --set ray_block=37"},
        Case{"PeRayGenerationBroadcastGatherAsFinished",
             "shells-1.nff --size 32x32 --pes 3 --set ray_generation=pe --set broadcast=true --set "
             "gather=as_finished"},
        // Units waiting for room in full feedback FIFOs, and rays spilling from the front buffer.
        Case{"FullFifosAndSpills",
             "mount-1.nff --size 32x32 --pes 2 --search-units 8 --set feedback_fifo_depth=1"
             " --set front_buffer_capacity=2"},
        Case{"UntilOccupiedFp64FullSchedule",
             "lattice-1.nff --size 32x32 --set search_walk=until_occupied --precision fp64 "
             "--mac-schedule full"},
        Case{"PixelsFewCredits",
             "jacks-1.nff --size 32x32 --pes 5 --partition pixels --set loop_credits=3"},
        // Several intersection units: the lowest idle one takes a ray; root units rank by lane.
        Case{"TwoIntersectionUnits", "tree-2.nff --size 40x40 --pes 2 --set intersection_units=2"},
        Case{"ThreeIntersectionUnitsTinyFifos",
             "shells-1.nff --size 32x32 --pes 3 --set intersection_units=3 --search-units 6 --set "
             "root_fifo_depth=2"
             " --set search_fifo_depth=2 --set feedback_fifo_depth=1"},
        // PEs with no pixels at all finish at once; one ray per transfer.
        Case{"MorePesThanPixels",
             "balls-1.nff --size 3x2 --pes 8 --set ray_block=1 --set gather=as_finished"},
        // Pipelining off, the paper's machine, and long intervals with full FIFOs stalling
        // pipelines.
        Case{"Unpipelined",
             "rings-1.nff --size 32x32 --pes 2 --set dispatch_interval=0 --set search_interval=0"
             " --set mac_streaming=false --set root_interval=0 --set shade_interval=0"},
        Case{"PaperPreset", "tree-2.nff --size 32x32 --pes 2 --preset paper"},
        Case{"LongIntervalsStallingPipelines",
             "mount-1.nff --size 32x32 --pes 2 --search-units 2 --set search_interval=3 --set "
             "shade_interval=5"
             " --set root_interval=4 --set dispatch_interval=2 --set feedback_fifo_depth=1 --set "
             "front_buffer_capacity=2"},
        // Rays landing while the PEs work, from a star's two ports and down a tree
        // (net/interconnect.h).
        Case{"StarStreamedRaysGatherAsFinished",
             "tree-2.nff --size 24x24 --pes 3 --set link_topology=star --set host_ports=2 --set "
             "ray_block=37"
             " --set gather=as_finished"},
        Case{"TreeBroadcastStreamedRays",
             "balls-2.nff --size 24x24 --pes 5 --set link_topology=tree --set broadcast=true --set "
             "ray_block=20"
             " --set gather=as_finished"},
        Case{"TreeCutThroughStreamedRays",
             "balls-2.nff --size 24x24 --pes 5 --set link_topology=tree --set "
             "tree_forwarding=cut_through --set ray_block=20 --set gather=as_finished"},
        Case{"StreamedGatherOnAStar",
             "rings-1.nff --size 24x24 --pes 3 --set link_topology=star --set host_ports=2 --set "
             "gather=streamed --set gather_block=7"},
        // Tiles on demand (partition = dynamic): the PEs ask as they go, the host answers over
        // the link, each PE's frame buffer grows by the tile.
        Case{"DynamicTiles", "balls-1.nff --size 30x26 --pes 3 --partition dynamic --set tile=7"},
        Case{"DynamicPeRaysOnATreeGatherAsFinished",
             "tree-2.nff --size 24x24 --pes 5 --partition dynamic --set tile=4 --set "
             "ray_generation=pe --set link_topology=tree --set broadcast=true --set "
             "gather=as_finished"},
        Case{"DynamicStreamedGatherOnAStar",
             "rings-1.nff --size 24x24 --pes 3 --partition dynamic --set tile=5 --set "
             "link_topology=star --set host_ports=2 --set gather=streamed --set gather_block=7"},
        Case{"DynamicMorePesThanTiles",
             "balls-1.nff --size 9x9 --pes 6 --partition dynamic --set tile=8 --set "
             "voxelisation=pe"},
        Case{"PeVoxelisationOnATree",
             "rings-1.nff --size 24x24 --pes 4 --set voxelisation=pe --set link_topology=tree "
             "--set broadcast=true --set ray_block=50"},
        Case{"StreamedSceneOnACutThroughTree",
             "rings-1.nff --size 24x24 --pes 4 --set voxelisation=pe --set link_topology=tree "
             "--set tree_forwarding=cut_through --set broadcast=true --set scene_block=3 --set "
             "gather=streamed"},
        // Several frames: each PE runs ahead within a frame, tells the host its end, and takes
        // the next frame's rays once it has switched (its voxel data built).
        Case{"FramesThroughAPipelinedHost",
             "balls-1.nff --size 24x24 --pes 3 --frames 3 --set voxelisation=pe --set "
             "gather=as_finished"},
        Case{"FramesStreamedOnATree",
             "rings-1.nff --size 24x24 --pes 4 --frames 3 --set ray_generation=pe --set "
             "link_topology=tree --set tree_forwarding=cut_through --set broadcast=true --set "
             "gather=streamed --set gather_block=9 --set scene_block=3"},
        // Clocked timing: the MAC at clock level, run edge by edge up to each of its actions,
        // holding while its result cannot leave (a one-deep root FIFO behind two MACs).
        Case{"ClockedTwoMacsHeldByAFullRootFifo",
             "rings-1.nff --size 24x24 --pes 2 --timing clocked --set intersection_units=2 --set "
             "root_fifo_depth=1 --set root_interval=0 --set root_latency=9 --set clock_ns=3.3"},
        Case{"ClockedPaperPresetFp64",
             "tree-2.nff --size 24x24 --pes 2 --preset paper --timing clocked --precision fp64"},
        Case{"SlowLinkNoLeaveOut",
             "balls-2.nff --size 24x24 --pes 2 --set link_bandwidth_mb_s=5 --set leave_out=false "
             "--set clock_ns=7"},
        // Each unit in its own precision, and the refinement's cycles moving shading's results.
        Case{"MixedPrecisionsSlowRefinement",
             "rings-1.nff --size 24x24 --pes 2 --set dda_precision=fp64 --set "
             "intersection_precision=fp32"
             " --set shading_precision=fp64 --set refine_cycles=40"}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

TEST(EngineMatchesModules, OnRandomSmallConfigurations) {
  std::mt19937 rng(1201);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  const char* scenes[] = {"balls-1.nff", "mount-1.nff", "tree-2.nff", "rings-1.nff"};
  for (int i = 0; i < 6; ++i) {
    std::ostringstream args;
    args << kScenes << scenes[i % 4] << random_small_machine(rng, 4)
         << " --set fb_dispatch_cycles=" << pick(1, 3) << " --set dda_step_cycles=" << pick(1, 3)
         << " --set memory_latency=" << pick(1, 9) << " --set intersection_units=" << pick(1, 3)
         << random_memory(rng);
    expect_engine_matches_modules(args.str());
  }
}

// The engines of several PEs run side by side on threads once their rays are in
// (machine/engine_driver.h): nothing may depend on how many threads there are, whether the PEs
// finish together, one by one as the host's rays reach them block by block, or with a gather as
// each finishes.
TEST(EngineOnThreads, TheFramesAreTheSameOnOneThreadAndOnSeveral) {
  for (const char* args :
       {"balls-2.nff --size 48x48 --pes 16",
        "tree-2.nff --size 40x40 --pes 7 --set ray_block=23 --set gather=as_finished"
        " --set intersection_units=2",
        "balls-1.nff --size 3x2 --pes 8 --set ray_block=1",
        "balls-2.nff --size 40x40 --pes 6 --partition dynamic --set tile=5",
        "balls-2.nff --size 32x32 --pes 5 --frames 3 --set ray_generation=pe"})
    for (const char* threads : {"--sim-threads 2", "--sim-threads 3"})
      expect_same_frame(kScenes + args, "--sim-threads 1", threads);
}

// The comparison names the first event where two runs part: here a shading unit one cycle slower,
// so the first difference is a put the slower shading unit makes later.
TEST(EngineMatchesModules, TheFirstDifferingEventIsNamed) {
  Tmp tmp;
  const std::string args = kScenes + "balls-1.nff --size 8x8 --event-log ";
  ASSERT_FALSE(render(tmp, "a", args + (tmp / "a.log")).is_null());
  ASSERT_FALSE(render(tmp, "b", args + (tmp / "b.log") + " --set shade_cycles=17").is_null());
  const std::string d = first_difference(slurp(tmp / "a.log"), slurp(tmp / "b.log"));
  ASSERT_NE(d, "");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      d, m,
      std::regex(
          R"(modules '(\d+ pe0 shading ray\d+) take (\d+)', engine '(\d+ pe0 shading ray\d+) take (\d+)')")))
      << d;
  EXPECT_EQ(m[1], m[3]) << "the same ray at the same cycle: " << d;
  EXPECT_EQ(std::stoi(m[4]), std::stoi(m[2]) + 1) << "one more shading cycle: " << d;
}

// The log's lines: cycle, PE, unit, ray, event and its detail (docs/architecture.md).
TEST(EngineMatchesModules, EventLogLinesSayWhoDidWhatWhen) {
  Tmp tmp;
  ASSERT_FALSE(
      render(tmp, "a", kScenes + "balls-1.nff --size 4x4 --pes 2 --event-log " + (tmp / "a.log"))
          .is_null());
  std::istringstream log(slurp(tmp / "a.log"));
  std::string line;
  int lines = 0, primaries = 0;
  uint64_t last_cycle = 0;
  const std::regex form(R"((\d+) pe[01] (front_buffer|search|mac0|root0|shading) ray\d+ )"
                        R"((take \d+( queued| spilled| primary)?|put [a-z_]+))");
  while (std::getline(log, line)) {
    std::smatch m;
    ASSERT_TRUE(std::regex_match(line, m, form)) << line;
    const uint64_t cycle = std::stoull(m[1]);
    EXPECT_GE(cycle, last_cycle) << "in cycle order: " << line;
    last_cycle = cycle;
    primaries += line.find(" primary") != std::string::npos;
    ++lines;
  }
  EXPECT_EQ(primaries, 16) << "one primary ray per pixel";
  EXPECT_GT(lines, 16 * 4);
}

TEST(EngineMatchesModules, WaveformsUseTheModulesClockedTimingTheEngine) {
  Tmp tmp;
  const json vcd = render(tmp, "vcd", kScenes + "balls-1.nff --size 8x8 --vcd " + (tmp / "w.vcd"));
  ASSERT_FALSE(vcd.is_null());
  EXPECT_FALSE(vcd["pe_simulation"]["engine"].get<bool>());
  EXPECT_NE(vcd["pe_simulation"]["modules_because"].get<std::string>().find("waveform"),
            std::string::npos);
  const json clocked = render(tmp, "clocked", kScenes + "balls-1.nff --size 8x8 --timing clocked");
  ASSERT_FALSE(clocked.is_null());
  EXPECT_TRUE(clocked["pe_simulation"]["engine"].get<bool>());
}

}  // namespace
