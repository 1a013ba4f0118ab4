// Runs of several frames (the key frames; docs/machine.md, "Several frames"): the same frame again,
// the host preparing and sending the next while the PEs render one. Only times move: every frame
// is the one-frame picture, with its IDs and rays; the link carries every frame's scene, rays and
// pixels; the steady state is no slower than one frame alone and no faster than the host's own
// work a frame; the modules in clocked timing give the engine's cycles.
#include <algorithm>
#include <filesystem>
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
const std::string kFrame = kScene + " --size 13x11";
// Every mechanism of docs/studies/scaling.md's machine that scales.
const std::string kAll =
    " --set ray_generation=pe --set broadcast=true --set search_walk=until_occupied --set "
    "gather=streamed --set voxelisation=pe --set link_topology=tree --set "
    "tree_forwarding=cut_through --set host_ports=2 --set scene_block=4 --partition pixels";

struct Case {
  const char* name;
  int pes, frames;
  std::string more;
};

const std::vector<Case> kCases = {
    {"two-frames", 3, 2, ""},
    {"as-finished", 4, 3, " --set gather=as_finished"},
    {"every-mechanism", 5, 3, kAll},
    {"paper", 2, 3, " --preset paper"},
    // Blocks of a 13x11 screen on 7 PEs: some PEs have no pixels and end no frames.
    {"pes-without-pixels", 7, 3, " --partition blocks --set tile=8"},
    {"clocked", 3, 3, " --timing clocked --set gather=as_finished"},
};

uint64_t u(const json& j) { return j.get<uint64_t>(); }

TEST(Frames, EveryFrameIsTheOneFramePictureWithItsIdsAndRays) {
  Tmp tmp;
  for (const Case& c : kCases) {
    const std::string args = kFrame + " --pes " + std::to_string(c.pes) + c.more;
    const json one = render(tmp, std::string(c.name) + "-one", args);
    const json many = render(tmp, c.name, args + " --frames " + std::to_string(c.frames));
    ASSERT_FALSE(one.is_null() || many.is_null()) << c.name;
    EXPECT_EQ(rtm::read_image(tmp / (std::string(c.name) + ".exr")).rgb,
              rtm::read_image(tmp / (std::string(c.name) + "-one.exr")).rgb)
        << c.name;
    EXPECT_EQ(rtm::read_id_map(tmp / (std::string(c.name) + "-id.exr")).ids,
              rtm::read_id_map(tmp / (std::string(c.name) + "-one-id.exr")).ids)
        << c.name;
    for (const auto& [kind, n] : one["rays"].items())
      EXPECT_EQ(u(many["rays"][kind]), c.frames * u(n)) << c.name << " " << kind;
    // One frame: its time is the run's.
    EXPECT_EQ(one["frames"]["count"], 1) << c.name;
    EXPECT_EQ(one["frames"]["done_cycles"], json::array({one["cycles"]})) << c.name;
    EXPECT_EQ(one["frames"]["steady_frame_cycles"].get<double>(), u(one["cycles"])) << c.name;
    // Several: each whole at the host after the one before, the run over with the last; the steady
    // state the mean of the frames after the first.
    const json& f = many["frames"];
    ASSERT_EQ(f["count"], c.frames) << c.name;
    uint64_t sum = 0, before = 0;
    for (size_t k = 0; k < size_t(c.frames); ++k) {
      const uint64_t done = f["done_cycles"][k], took = f["frame_cycles"][k];
      EXPECT_GT(done, before) << c.name << " frame " << k;
      EXPECT_EQ(took, done - before) << c.name << " frame " << k;
      sum += took;
      before = done;
    }
    EXPECT_EQ(sum, u(many["cycles"])) << c.name;
    EXPECT_DOUBLE_EQ(f["steady_frame_cycles"].get<double>(),
                     double(before - u(f["done_cycles"][0])) / (c.frames - 1))
        << c.name;
    EXPECT_EQ(many["summary"]["frame_cycles"], f["steady_frame_cycles"]) << c.name;
    // The first frame's transfers are the one-frame machine's, but that a PE's pixels go on the
    // links as it ends the frame, between the host's transfers to the PEs after it: no PE starts
    // earlier, and the frame is whole at the host after every PE of the one-frame machine is done.
    uint64_t last_pe = 0;
    for (size_t pe = 0; pe < many["per_pe"].size(); ++pe) {
      EXPECT_GE(u(many["per_pe"][pe]["start_cycle"]), u(one["per_pe"][pe]["start_cycle"]))
          << c.name;
      last_pe = std::max(last_pe, u(one["per_pe"][pe]["cycles"]));
    }
    EXPECT_GT(u(f["done_cycles"][0]), last_pe) << c.name;
    // Each local memory holds two frames' scenes, rays and frame buffers.
    for (size_t pe = 0; pe < many["per_pe"].size(); ++pe)
      EXPECT_EQ(u(many["per_pe"][pe]["memory_used_bytes"]),
                2 * u(one["per_pe"][pe]["memory_used_bytes"]))
          << c.name << " PE " << pe;
  }
}

// balls-1 on 4 PEs: the host's framing and voxel data take a large part of one frame. Pipelined,
// a frame of the steady state takes less than one frame alone, and no less than what the host
// does for a frame by itself.
TEST(Frames, TheHostPreparesTheNextFrameWhileThePesRenderThisOne) {
  Tmp tmp;
  const std::string args = kScene + " --size 24x24 --pes 4";
  const json one = render(tmp, "one", args);
  const json many = render(tmp, "many", args + " --frames 4");
  ASSERT_FALSE(one.is_null() || many.is_null());
  const double steady = many["frames"]["steady_frame_cycles"];
  EXPECT_LT(steady, 0.95 * u(one["cycles"]));
  EXPECT_GE(steady, u(many["host"]["work_cycles"]) / 4.0);
  // Between frames a PE waits for the next frame's scene.
  for (const json& pe : many["per_pe"]) EXPECT_GT(u(pe["frame_wait_cycles"]), 0u);
  for (const json& pe : one["per_pe"]) EXPECT_EQ(u(pe["frame_wait_cycles"]), 0u);
}

// One serial link: every frame's scene copies, rays and pixels, as many bytes as that many single
// frames; the cost is a frame's share of the work.
TEST(Frames, TheLinkCarriesEveryFrame) {
  Tmp tmp;
  for (const std::string& more : {std::string(), kAll}) {
    const std::string args = kFrame + " --pes 3" + more;
    const json one = render(tmp, "one", args);
    const json many = render(tmp, "many", args + " --frames 3");
    ASSERT_FALSE(one.is_null() || many.is_null());
    EXPECT_EQ(u(many["interconnect"]["bytes"]), 3 * u(one["interconnect"]["bytes"])) << more;
    EXPECT_NEAR(many["summary"]["energy_link_j"].get<double>(),
                one["summary"]["energy_link_j"].get<double>(),
                1e-9 * one["summary"]["energy_link_j"].get<double>())
        << more;
  }
}

TEST(Frames, ClockedTimingGivesTheFastCycles) {
  Tmp tmp;
  const std::string args = kFrame + " --pes 4 --frames 3" + kAll;
  const json fast = render(tmp, "fast", args);
  const json clocked = render(tmp, "clocked", args + " --timing clocked");
  ASSERT_FALSE(fast.is_null() || clocked.is_null());
  EXPECT_TRUE(fast["pe_simulation"]["engine"].get<bool>());
  EXPECT_EQ(clocked["cycles"], fast["cycles"]);
  EXPECT_EQ(clocked["frames"], fast["frames"]);
  EXPECT_EQ(clocked["host"], fast["host"]);
  EXPECT_EQ(clocked["per_pe"], fast["per_pe"]);
}

TEST(Frames, ADynamicPartitionOrStreamedRaysAreRefused) {
  Tmp tmp;
  for (const std::string& bad :
       {std::string("--partition dynamic"), std::string("--set ray_block=10")}) {
    const Proc r =
        run_rtm("render " + kFrame + " --frames 2 " + bad + " -q --out " + (tmp / "x.exr"), tmp);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("frames: 2 with"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(tmp / "x.exr")) << bad;
  }
}

}  // namespace
