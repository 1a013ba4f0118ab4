// The interconnect in whole renders (net/interconnect.h; docs/machine.md, "The host-PE
// interconnect"): every topology gives the same image, only other times; the links carry the bytes
// the transfers add up to; the topologies that overlap transfers finish them sooner; the
// combination that cannot be built is refused naming its keys.
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
constexpr int kWidth = 12, kHeight = 12, kPes = 5;
constexpr uint64_t kRayBytes = 28, kPixelBytes = 16;  // machine/host.h

struct Net {
  const char* name;
  std::string args;
  std::string topology;
  int host_ports = 1, fanout = 2;
  bool broadcast = false;
};

/// Hops from the host to PE `pe` on a tree: the host's host_ports children are PEs 0..h-1, PE i's
/// children PEs h + f·i ... h + f·i + f - 1 (docs/machine.md).
int tree_depth(int pe, int h, int f) { return pe < h ? 1 : 1 + tree_depth((pe - h) / f, h, f); }

/// A mechanism that moves only times leaves each PE's work as it was: its rays, busy and issue
/// cycles, memory accesses and the length of its working window (its start may move).
void expect_same_pe_work(const json& moved, const json& base, size_t pe) {
  for (const char* key : {"rays", "busy_cycles", "issue_cycles", "memory_access"})
    EXPECT_EQ(moved[key], base[key]) << "PE " << pe << " " << key;
  EXPECT_EQ(moved["cycles"].get<int64_t>() - moved["start_cycle"].get<int64_t>(),
            base["cycles"].get<int64_t>() - base["start_cycle"].get<int64_t>())
      << "PE " << pe << "'s working window";
}

/// What every link together carries: the scene once (a broadcast on one medium), once per link
/// (a broadcast on a star or a tree), or once per PE and hop; each PE's rays and frame buffer
/// once per hop. Scanlines: PE i renders the rows y with y mod N = i.
uint64_t expected_bytes(const Net& n, uint64_t scene_bytes) {
  const bool one_medium = n.topology == "serial" || n.topology == "bus";
  uint64_t total = n.broadcast && one_medium ? scene_bytes : 0;
  for (int pe = 0; pe < kPes; ++pe) {
    const uint64_t pixels = uint64_t(kWidth) * uint64_t((kHeight - pe + kPes - 1) / kPes);
    const uint64_t hops =
        n.topology == "tree" ? uint64_t(tree_depth(pe, n.host_ports, n.fanout)) : 1;
    if (!n.broadcast) total += scene_bytes * hops;
    if (n.broadcast && !one_medium) total += scene_bytes;
    total += pixels * (kRayBytes + kPixelBytes) * hops;
  }
  return total;
}

Net net(const char* name, const std::string& topology, int host_ports, int fanout, bool broadcast,
        const std::string& more = "") {
  Net n{name, "", topology, host_ports, fanout, broadcast};
  n.args = " --set link_topology=" + topology + " --set host_ports=" + std::to_string(host_ports) +
           " --set tree_fanout=" + std::to_string(fanout) +
           " --set broadcast=" + (broadcast ? "true" : "false") + more;
  return n;
}

TEST(InterconnectRender, EveryTopologyGivesTheSameImageAndItsLinksAddUp) {
  Tmp tmp;
  const std::string frame = kScene + " --size " + std::to_string(kWidth) + "x" +
                            std::to_string(kHeight) + " --pes " + std::to_string(kPes);
  const std::vector<Net> nets = {
      net("serial", "serial", 1, 2, false),
      net("serial-broadcast", "serial", 1, 2, true),
      net("bus", "bus", 1, 2, false),
      net("bus-broadcast", "bus", 1, 2, true),
      net("star-2", "star", 2, 2, false),
      net("star-5-broadcast", "star", 5, 2, true),
      net("tree-2", "tree", 1, 2, false),
      net("tree-broadcast", "tree", 1, 2, true),
      net("tree-chain-broadcast", "tree", 2, 1, true),
      net("star-streamed-as-finished", "star", 3, 2, false,
          " --set ray_block=10 --set gather=as_finished"),
      net("tree-streamed-as-finished", "tree", 1, 3, true,
          " --set ray_block=10 --set gather=as_finished"),
      net("tree-2-cut-through", "tree", 1, 2, false, " --set tree_forwarding=cut_through"),
      net("tree-broadcast-cut-through", "tree", 1, 2, true, " --set tree_forwarding=cut_through"),
      net("tree-chain-cut-through-streamed", "tree", 1, 1, true,
          " --set tree_forwarding=cut_through --set ray_block=10 --set gather=as_finished"),
  };
  const json serial = render(tmp, "serial", frame + nets[0].args);
  ASSERT_FALSE(serial.is_null());
  const auto serial_rgb = rtm::read_image(tmp / "serial.exr").rgb;
  const auto serial_ids = rtm::read_id_map(tmp / "serial-id.exr").ids;
  const uint64_t scene_bytes = serial["host"]["scene_bytes"];
  for (const Net& n : nets) {
    const json j = n.name == std::string("serial") ? serial : render(tmp, n.name, frame + n.args);
    ASSERT_FALSE(j.is_null()) << n.name;
    EXPECT_EQ(rtm::read_image(tmp / (std::string(n.name) + ".exr")).rgb, serial_rgb)
        << n.name << ": timing only";
    EXPECT_EQ(rtm::read_id_map(tmp / (std::string(n.name) + "-id.exr")).ids, serial_ids) << n.name;
    EXPECT_EQ(j["rays"], serial["rays"]) << n.name;
    const json& ic = j["interconnect"];
    EXPECT_EQ(ic["topology"], n.topology);
    const bool one_medium = n.topology == "serial" || n.topology == "bus";
    ASSERT_EQ(ic["links"].size(), one_medium ? 1u : size_t(kPes)) << n.name;
    uint64_t bytes = 0;
    double seconds = 0;
    for (size_t i = 0; i < ic["links"].size(); ++i) {
      const json& l = ic["links"][i];
      EXPECT_EQ(l["name"],
                one_medium ? (n.topology == "bus" ? "bus" : "link") : "pe" + std::to_string(i));
      EXPECT_GT(l["transfers"].get<uint64_t>(), 0u) << n.name << " " << l["name"];
      bytes += l["bytes"].get<uint64_t>();
      seconds += l["busy_seconds"].get<double>();
    }
    EXPECT_EQ(ic["bytes"].get<uint64_t>(), bytes) << n.name;
    EXPECT_EQ(bytes, expected_bytes(n, scene_bytes)) << n.name;
    EXPECT_NEAR(ic["busy_seconds"].get<double>(), seconds, 1e-12) << n.name;
    EXPECT_EQ(ic["busy_cycles"], j["host"]["link_busy_cycles"]) << n.name;
    EXPECT_EQ(ic["busy_cycles"], j["summary"]["link_busy_cycles"]) << n.name;
    // Latency and bytes at 400 MB/s, 10 ns cycles: 100 cycles a transfer and 4 bytes a cycle.
    uint64_t transfers = 0;
    for (const json& l : ic["links"]) transfers += l["transfers"].get<uint64_t>();
    EXPECT_NEAR(ic["busy_cycles"].get<double>(), 100.0 * double(transfers) + double(bytes) / 4, 1.0)
        << n.name;
  }
  // One medium gives the same times whichever it is called; a star or a tree overlaps transfers.
  const json bus = json::parse(slurp(tmp / "bus.json"));
  EXPECT_EQ(bus["cycles"], serial["cycles"]);
  EXPECT_EQ(json::parse(slurp(tmp / "bus-broadcast.json"))["cycles"],
            json::parse(slurp(tmp / "serial-broadcast.json"))["cycles"]);
  const uint64_t serial_transfer = serial["host"]["transfer_done_cycle"];
  // Each PE starts when its rays arrive. On the star with two ports (each hop 100 cycles and 4
  // bytes a cycle: the scene S, PE i's rays R_i) PEs 0 and 1 get theirs after one scene, PEs 2
  // and 3 on the ports freed after S + R_0, PE 4 on port 0 again after S + R_0 + S + R_2.
  const json star = json::parse(slurp(tmp / "star-2.json"));
  const double S = 100 + double(scene_bytes) / 4;
  auto rays = [](int pe) {
    return 100 + double(kWidth * ((kHeight - pe + kPes - 1) / kPes) * kRayBytes) / 4;
  };
  const double starts[kPes] = {S, S, 2 * S + rays(0), 2 * S + rays(1), 3 * S + rays(0) + rays(2)};
  for (int pe = 0; pe < kPes; ++pe)
    EXPECT_NEAR(star["per_pe"][pe]["start_cycle"].get<double>() -
                    star["host"]["rays_done_cycle"].get<double>(),
                starts[pe], 1.0)
        << "PE " << pe;
  for (const char* faster : {"star-2", "star-5-broadcast", "tree-broadcast"})
    EXPECT_LT(
        json::parse(slurp(tmp / (std::string(faster) + ".json")))["host"]["transfer_done_cycle"]
            .get<uint64_t>(),
        serial_transfer)
        << faster;
}

// Cut-through moves only times: the same work on every PE, the links busy as long.
TEST(InterconnectRender, CutThroughOnATreeMovesOnlyTheTimes) {
  Tmp tmp;
  const std::string args = kScene + " --size " + std::to_string(kWidth) + "x" +
                           std::to_string(kHeight) + " --pes " + std::to_string(kPes) +
                           " --set link_topology=tree --set broadcast=true";
  const json stored = render(tmp, "stored", args);
  const json cut = render(tmp, "cut", args + " --set tree_forwarding=cut_through");
  ASSERT_FALSE(stored.is_null() || cut.is_null());
  EXPECT_EQ(rtm::read_image(tmp / "cut.exr").rgb, rtm::read_image(tmp / "stored.exr").rgb);
  for (const char* key : {"rays", "intersection_tests", "voxel_steps"})
    EXPECT_EQ(cut[key], stored[key]) << key;
  ASSERT_EQ(cut["per_pe"].size(), stored["per_pe"].size());
  for (size_t pe = 0; pe < cut["per_pe"].size(); ++pe) {
    const json &c = cut["per_pe"][pe], &s = stored["per_pe"][pe];
    expect_same_pe_work(c, s, pe);
    if (pe == 0)  // one link deep: nothing to forward
      EXPECT_EQ(c["start_cycle"], s["start_cycle"]);
    else
      EXPECT_LT(c["start_cycle"].get<uint64_t>(), s["start_cycle"].get<uint64_t>()) << "PE " << pe;
  }
  EXPECT_EQ(cut["interconnect"]["bytes"], stored["interconnect"]["bytes"]);
  EXPECT_EQ(cut["interconnect"]["busy_cycles"], stored["interconnect"]["busy_cycles"]);
  EXPECT_LT(cut["cycles"].get<uint64_t>(), stored["cycles"].get<uint64_t>());
}

// By hand, on a chain of 2 PEs with rays made on the PEs (each hop L = 100 cycles of latency and
// 4 bytes a cycle: the scene S, a camera record C = L + 16). Store-and-forward: the scene holds
// link 0 over [0, S) and link 1 over [S, 2S); PE 1's camera follows PE 0's on link 0 to S + 2C,
// then waits for link 1 until 2S. Cut-through: the scene holds link 1 over [L, L + S); PE 1's
// camera leaves link 0 at S + C and goes on L later, at S + C + L, link 1 being free by then. So
// PE 1 starts S - C - L sooner, and PE 0, one link deep, at the same cycle.
TEST(InterconnectRender, CutThroughOnAChainByHand) {
  Tmp tmp;
  const std::string args = kScene +
                           " --size 8x8 --pes 2 --set link_topology=tree --set "
                           "tree_fanout=1 --set broadcast=true --set ray_generation=pe";
  const json stored = render(tmp, "stored", args);
  const json cut = render(tmp, "cut", args + " --set tree_forwarding=cut_through");
  ASSERT_FALSE(stored.is_null() || cut.is_null());
  const double L = 100, S = L + stored["host"]["scene_bytes"].get<double>() / 4, C = L + 16;
  EXPECT_EQ(cut["per_pe"][0]["start_cycle"], stored["per_pe"][0]["start_cycle"]);
  EXPECT_NEAR(stored["per_pe"][1]["start_cycle"].get<double>() -
                  cut["per_pe"][1]["start_cycle"].get<double>(),
              S - C - L, 1.0);
}

// A streamed gather moves only the gather: the same image and work on every PE, the frame buffers
// carried once more with a 4-byte header a block, and the frame's tail after the last PE a block's
// hop rather than a whole frame buffer's (each hop 100 cycles of latency and 4 bytes a cycle).
TEST(InterconnectRender, AStreamedGatherOverlapsTheGatherWithTheRendering) {
  Tmp tmp;
  constexpr int kBlock = 12;  // divides each PE's pixels: 144 on 1 PE, 36 or 24 of 12x12 on 5
  for (int pes : {1, kPes}) {
    const std::string args = kScene + " --size " + std::to_string(kWidth) + "x" +
                             std::to_string(kHeight) + " --pes " + std::to_string(pes);
    const std::string after = "after" + std::to_string(pes),
                      streamed = "streamed" + std::to_string(pes);
    const json a = render(tmp, after, args);
    const json s =
        render(tmp, streamed,
               args + " --set gather=streamed --set gather_block=" + std::to_string(kBlock));
    ASSERT_FALSE(a.is_null() || s.is_null());
    EXPECT_EQ(rtm::read_image(tmp / (streamed + ".exr")).rgb,
              rtm::read_image(tmp / (after + ".exr")).rgb);
    EXPECT_EQ(rtm::read_id_map(tmp / (streamed + "-id.exr")).ids,
              rtm::read_id_map(tmp / (after + "-id.exr")).ids);
    EXPECT_EQ(s["rays"], a["rays"]);
    EXPECT_EQ(s["per_pe"], a["per_pe"]) << "the PEs' work and times are the same";
    EXPECT_EQ(s["host"]["pes_done_cycle"], a["host"]["pes_done_cycle"]);
    uint64_t blocks = 0;
    for (int pe = 0; pe < pes; ++pe) {
      const uint64_t pixels = uint64_t(kWidth) * uint64_t((kHeight - pe + pes - 1) / pes);
      blocks += (pixels + kBlock - 1) / kBlock;
    }
    EXPECT_EQ(s["interconnect"]["bytes"].get<uint64_t>(),
              a["interconnect"]["bytes"].get<uint64_t>() + 4 * blocks);
    EXPECT_EQ(s["interconnect"]["links"][0]["transfers"].get<uint64_t>(),
              a["interconnect"]["links"][0]["transfers"].get<uint64_t>() + blocks - pes);
    const double tail = s["phases"]["gather_cycles"], after_tail = a["phases"]["gather_cycles"];
    const double block_hop = 100 + (4 + 16.0 * kBlock) / 4;
    EXPECT_GE(tail, block_hop - 1) << pes << " PEs: the last block goes after the last pixel";
    EXPECT_LT(tail, after_tail) << pes << " PEs";
    EXPECT_LT(s["cycles"].get<uint64_t>(), a["cycles"].get<uint64_t>()) << pes << " PEs";
    if (pes == 1) {  // after all: one frame buffer of 144 pixels after the PE
      EXPECT_NEAR(after_tail, 100 + 144 * 16 / 4.0, 1.0);
    }
  }
}

// A PE-engine frame and a modules frame agree on every topology (engine_test.cpp compares two
// streamed ones event by event); so do fast and clocked timing, also with every mechanism of a
// machine that scales on.
TEST(InterconnectRender, FastAndClockedTimingAgreeOnATreeAndAStar) {
  Tmp tmp;
  for (const std::string topology :
       {"tree --set broadcast=true", "star --set host_ports=2",
        "tree --set broadcast=true --set tree_forwarding=cut_through --set voxelisation=pe --set "
        "scene_block=3 --set gather=streamed --set gather_block=5"}) {
    const std::string args = kScene + " --size 6x6 --pes 3 --set link_topology=" + topology;
    const json fast = render(tmp, "fast", args);
    const json clocked = render(tmp, "clocked", args + " --timing clocked");
    ASSERT_FALSE(fast.is_null() || clocked.is_null());
    EXPECT_EQ(fast["cycles"], clocked["cycles"]) << topology;
    EXPECT_EQ(fast["host"], clocked["host"]) << topology;
    EXPECT_EQ(fast["interconnect"], clocked["interconnect"]) << topology;
    EXPECT_EQ(rtm::read_image(tmp / "fast.exr").rgb, rtm::read_image(tmp / "clocked.exr").rgb)
        << topology;
  }
}

// One scene transfer cannot reach every PE of a star unless the host drives every link at once.
TEST(InterconnectRender, ABroadcastOnAStarWithTooFewPortsIsRefusedNamingTheKeys) {
  Tmp tmp;
  const std::string args =
      "render " + kScene + " --size 4x4 --pes 4 --set link_topology=star --set broadcast=true -q";
  const Proc refused = run_rtm(args + " --set host_ports=3 --out " + (tmp / "x.png"), tmp);
  EXPECT_EQ(refused.exit_code, 2);
  for (const char* word : {"broadcast", "link_topology = star", "host_ports >= pes (3 < 4)"})
    EXPECT_NE(refused.err.find(word), std::string::npos) << word << "\n" << refused.err;
  EXPECT_FALSE(std::filesystem::exists(tmp / "x.png"));
  const Proc enough = run_rtm(args + " --set host_ports=4 --out " + (tmp / "o.png"), tmp);
  EXPECT_EQ(enough.exit_code, 0) << enough.err;
}

// The printed summary has the interconnect's line: topology, links, ports, bytes, busy cycles.
TEST(InterconnectRender, TheSummarySaysWhatTheLinksCarried) {
  Tmp tmp;
  const Proc r =
      run_rtm("render " + kScene +
                  " --size 4x4 --pes 2 --set link_topology=tree --set host_ports=2 --out " +
                  (tmp / "o.png"),
              tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(tmp / "o.json"));
  const std::string line = "interconnect: tree, 2 links, 2 host ports: " +
                           std::to_string(j["interconnect"]["bytes"].get<uint64_t>()) +
                           " bytes, busy " +
                           std::to_string(j["interconnect"]["busy_cycles"].get<uint64_t>()) +
                           " cycles over all links; the busiest, pe";
  EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
}

}  // namespace

// Streamed rays interleave the host's work and the link's: the phases tell them apart, so a link
// too slow to feed the PEs is named, and so is a host too slow to make the rays.
TEST(InterconnectRender, StreamedRaysNameTheSlowLinkOrTheSlowHost) {
  Tmp tmp;
  const std::string args =
      kScene + " --size 16x16 --pes 2 --set ray_block=8 --set host_voxel_cycles=0";
  const json link =
      render(tmp, "link", args + " --set host_ray_cycles=1 --set link_bandwidth_mb_s=0.5");
  const json host =
      render(tmp, "host", args + " --set host_ray_cycles=60000 --set link_bandwidth_mb_s=1000");
  ASSERT_FALSE(link.is_null() || host.is_null());
  EXPECT_EQ(link["bottleneck"], "interconnect") << link["bottleneck_reason"];
  EXPECT_EQ(host["bottleneck"], "host_preprocessing") << host["bottleneck_reason"];
  for (const json* j : {&link, &host}) {
    EXPECT_NEAR((*j)["host"]["work_cycles"].get<double>(),
                (*j)["phases"]["host_preprocess_cycles"].get<double>(), 1.0);
    const json& p = (*j)["phases"];
    EXPECT_NEAR(p["host_preprocess_cycles"].get<double>() + p["transfer_cycles"].get<double>() +
                    p["pe_cycles"].get<double>() + p["gather_cycles"].get<double>(),
                (*j)["cycles"].get<double>(), 1.0)
        << "the four phases add up to the frame";
  }
  EXPECT_LT(link["phases"]["host_preprocess_cycles"].get<double>(),
            link["phases"]["transfer_cycles"].get<double>());
  EXPECT_GT(host["phases"]["host_preprocess_cycles"].get<double>(),
            host["phases"]["transfer_cycles"].get<double>());
}

// voxelisation = pe: the scene crosses the link without its voxel data and each PE builds its own
// before its first ray. Only times and the link's bytes move: worked out by hand on 1 PE (rays
// made on the PE, so a camera record follows the scene), the grid's V voxels and R references
// from the statistics: the host saves host_voxel_cycles (40) a reference, the link 4 (V + 1 + R)
// bytes at 4 a cycle, and the PE spends pe_voxel_cycles (2) a reference and 4 (V + 1) bytes of
// offsets written 16 a cycle, before its first ray.
TEST(InterconnectRender, PeVoxelisationMovesTheGridBuildOntoThePes) {
  Tmp tmp;
  for (int pes : {1, 3}) {
    const std::string args = kScene + " --size 8x8 --pes " + std::to_string(pes) +
                             " --set ray_generation=pe --set broadcast=true";
    const std::string host = "host" + std::to_string(pes), pe = "pe" + std::to_string(pes);
    const json h = render(tmp, host, args);
    const json p = render(tmp, pe, args + " --set voxelisation=pe");
    ASSERT_FALSE(h.is_null() || p.is_null());
    EXPECT_EQ(rtm::read_image(tmp / (pe + ".exr")).rgb, rtm::read_image(tmp / (host + ".exr")).rgb);
    EXPECT_EQ(rtm::read_id_map(tmp / (pe + "-id.exr")).ids,
              rtm::read_id_map(tmp / (host + "-id.exr")).ids);
    EXPECT_EQ(p["rays"], h["rays"]);
    ASSERT_EQ(p["per_pe"].size(), size_t(pes));
    for (int i = 0; i < pes; ++i) expect_same_pe_work(p["per_pe"][i], h["per_pe"][i], size_t(i));
    const uint64_t refs = h["grid"]["references"];
    uint64_t voxels = 1;
    for (const json& n : h["grid"]["resolution"]) voxels *= n.get<uint64_t>();
    const uint64_t voxel_bytes = 4 * (voxels + 1 + refs),
                   build = 2 * refs + (4 * (voxels + 1) + 15) / 16;
    EXPECT_EQ(h["host"]["pe_voxelisation_cycles"], 0u);
    EXPECT_EQ(p["host"]["pe_voxelisation_cycles"], build);
    EXPECT_EQ(h["host"]["work_cycles"].get<uint64_t>() - p["host"]["work_cycles"].get<uint64_t>(),
              40 * refs);
    EXPECT_EQ(h["host"]["scene_bytes"].get<uint64_t>() - p["host"]["scene_bytes"].get<uint64_t>(),
              voxel_bytes);
    EXPECT_EQ(
        h["interconnect"]["bytes"].get<uint64_t>() - p["interconnect"]["bytes"].get<uint64_t>(),
        voxel_bytes)
        << "one broadcast";
    if (pes == 1) {
      EXPECT_NEAR(
          p["per_pe"][0]["start_cycle"].get<double>() - h["per_pe"][0]["start_cycle"].get<double>(),
          double(build) - 40.0 * double(refs) - double(voxel_bytes) / 4, 1.0);
    }
    EXPECT_EQ(h["cost"]["voxelisation_dynamic_j"], 0.0);
    const double voxelising = p["cost"]["voxelisation_dynamic_j"];
    EXPECT_GT(voxelising, 0.0);
    EXPECT_NEAR(p["cost"]["units"]["search"]["dynamic_j"].get<double>() -
                    h["cost"]["units"]["search"]["dynamic_j"].get<double>(),
                voxelising, 1e-9 * voxelising)
        << "the search units' steppers build it";
    EXPECT_LT(p["cycles"].get<uint64_t>(), h["cycles"].get<uint64_t>());
  }
}

// scene_block: the host frames the scene a block of primitives at a time and sends each block
// while it frames the next; a PE voxelising registers each block's references as it arrives. Only
// times move: the same image, rays, per-PE work and bytes on the link, a transfer more per block.
// One block holding every primitive is the unstreamed machine to the cycle; with a host slow to
// frame (host_frame_cycles 400: 4800 cycles for balls-1's 11 primitives, a light and the camera,
// against about 40 cycles a block on the link) the transfers hide behind the framing and the frame
// ends sooner.
TEST(InterconnectRender, StreamedSceneOverlapsFramingWithTheLink) {
  Tmp tmp;
  constexpr int kPrimitives = 11, kBlock = 2, kBlocks = (kPrimitives + kBlock - 1) / kBlock;
  for (const std::string voxelisation : {"pe", "host"}) {
    const std::string args = kScene +
                             " --size 8x8 --pes 3 --set ray_generation=pe --set broadcast=true "
                             "--set host_frame_cycles=400 --set voxelisation=" +
                             voxelisation;
    const std::string whole = "whole-" + voxelisation, one = "one-" + voxelisation,
                      streamed = "streamed-" + voxelisation;
    const json w = render(tmp, whole, args);
    const json o = render(tmp, one, args + " --set scene_block=" + std::to_string(kPrimitives));
    const json s = render(tmp, streamed, args + " --set scene_block=" + std::to_string(kBlock));
    ASSERT_FALSE(w.is_null() || o.is_null() || s.is_null());
    EXPECT_EQ(rtm::read_image(tmp / (streamed + ".exr")).rgb,
              rtm::read_image(tmp / (whole + ".exr")).rgb);
    EXPECT_EQ(rtm::read_id_map(tmp / (streamed + "-id.exr")).ids,
              rtm::read_id_map(tmp / (whole + "-id.exr")).ids);
    EXPECT_EQ(s["rays"], w["rays"]);
    for (int i = 0; i < 3; ++i) expect_same_pe_work(s["per_pe"][i], w["per_pe"][i], size_t(i));
    EXPECT_EQ(s["interconnect"]["bytes"], w["interconnect"]["bytes"]);
    EXPECT_EQ(s["host"]["work_cycles"], w["host"]["work_cycles"]) << "the same framing";
    // The primitives in kBlocks transfers (the voxel data in one more) instead of one.
    const uint64_t more = voxelisation == "pe" ? kBlocks - 1 : kBlocks;
    EXPECT_EQ(s["interconnect"]["links"][0]["transfers"].get<uint64_t>(),
              w["interconnect"]["links"][0]["transfers"].get<uint64_t>() + more);
    EXPECT_LT(s["host"]["transfer_done_cycle"].get<uint64_t>(),
              w["host"]["transfer_done_cycle"].get<uint64_t>());
    EXPECT_LT(s["cycles"].get<uint64_t>(), w["cycles"].get<uint64_t>());
    const json& p = s["phases"];
    EXPECT_NEAR(p["host_preprocess_cycles"].get<double>() + p["transfer_cycles"].get<double>() +
                    p["pe_cycles"].get<double>() + p["gather_cycles"].get<double>(),
                s["cycles"].get<double>(), 1.0)
        << "the four phases add up to the frame";
    if (voxelisation == "pe") {
      // The blocks' references are registered as they come: what is left after the last block
      // is less than the whole build.
      EXPECT_LT(s["host"]["pe_voxelisation_cycles"].get<uint64_t>(),
                w["host"]["pe_voxelisation_cycles"].get<uint64_t>());
      for (const char* key : {"cycles", "host", "interconnect", "per_pe"})
        EXPECT_EQ(o[key], w[key]) << key << ": one block is the whole scene";
    }
  }
}
