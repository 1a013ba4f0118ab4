// Pipelined units move timing only (docs/machine.md, "Pipelined units"): the same picture, ID
// map and rays with pipelining on and off; fast and clocked timing agree exactly under both
// presets and both MAC schedules; and the clocked MAC's waveform shows which sum its adder
// accumulates (abg_select) and hands on α, β, γ at the cycles the schedule gives.
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"

using nlohmann::json;
using namespace rtm::test;

namespace {

const std::string kScenes = std::string(RTM_SOURCE_DIR) + "/scenes/spd/";
const std::string kUnpipelined =
    " --set dispatch_interval=0 --set search_interval=0 --set mac_streaming=false --set "
    "root_interval=0"
    " --set shade_interval=0";

TEST(Pipelining, MovesTimingOnly) {
  for (const std::string schedule : {"sparse", "full"}) {
    Tmp tmp;
    // Reflections and refractions: every path of the loop.
    const std::string args =
        kScenes + "shells-1.nff --size 32x32 --pes 2 --mac-schedule " + schedule;
    const json on = render(tmp, "on", args);
    const json off = render(tmp, "off", args + kUnpipelined);
    ASSERT_FALSE(on.is_null() || off.is_null()) << schedule;
    EXPECT_EQ(rtm::read_image(tmp / "on.exr").rgb, rtm::read_image(tmp / "off.exr").rgb)
        << schedule;
    EXPECT_EQ(rtm::read_id_map(tmp / "on-id.exr").ids, rtm::read_id_map(tmp / "off-id.exr").ids)
        << schedule;
    for (const char* key : {"rays", "voxel_steps", "intersection_tests"})
      EXPECT_EQ(on[key], off[key]) << key;
    EXPECT_EQ(on["mac"]["products"], off["mac"]["products"]);
    EXPECT_LT(on["cycles"].get<uint64_t>(), off["cycles"].get<uint64_t>())
        << "pipelining buys cycles";
  }
}

TEST(Pipelining, FastAndClockedAgreeUnderBothPresetsAndSchedules) {
  for (const std::string preset : {"default", "paper"})
    for (const std::string schedule : {"sparse", "full"}) {
      Tmp tmp;
      const std::string args = kScenes + "rings-1.nff --size 16x16 --pes 2 --preset " + preset +
                               " --mac-schedule " + schedule;
      const json fast = render(tmp, "fast", args + " --event-log " + (tmp / "fast.log"));
      const json clocked =
          render(tmp, "clocked", args + " --timing clocked --event-log " + (tmp / "clocked.log"));
      ASSERT_FALSE(fast.is_null() || clocked.is_null()) << preset << " " << schedule;
      EXPECT_EQ(fast["cycles"], clocked["cycles"]) << preset << " " << schedule;
      EXPECT_EQ(slurp(tmp / "fast.log"), slurp(tmp / "clocked.log")) << preset << " " << schedule;
      EXPECT_EQ(rtm::read_image(tmp / "fast.exr").rgb, rtm::read_image(tmp / "clocked.exr").rgb);
    }
}

/// The value changes of one VCD signal (by its name's last two parts, e.g. "mac/abg_select"),
/// as time -> value text, from the first PE's first intersection unit.
std::map<uint64_t, std::string> changes(const std::string& vcd, const std::string& unit,
                                        const std::string& name) {
  std::istringstream in(vcd);
  std::string line, id;
  std::vector<std::string> scope;
  std::map<uint64_t, std::string> out;
  uint64_t t = 0;
  while (std::getline(in, line)) {
    std::istringstream w(line);
    std::string first;
    w >> first;
    if (first == "$scope") {
      std::string kind, s;
      w >> kind >> s;
      scope.push_back(s);
    } else if (first == "$upscope") {
      scope.pop_back();
    } else if (first == "$var") {
      std::string type, width, code, var;
      w >> type >> width >> code >> var;
      const bool here = scope.size() >= 3 && scope[scope.size() - 3] == "pe0" &&
                        scope[scope.size() - 2] == "intersection0" && scope.back() == unit;
      if (here && var == name) id = code;
    } else if (!first.empty() && first[0] == '#') {
      t = std::stoull(first.substr(1));
    } else if (!id.empty() && (first[0] == 'b' || first[0] == 'r')) {
      std::string code;
      w >> code;
      if (code == id) out[t] = first.substr(1);
    } else if (!id.empty() && (first[0] == '0' || first[0] == '1') && first.substr(1) == id) {
      out[t] = first.substr(0, 1);
    }
  }
  return out;
}

TEST(Pipelining, TheClockedMacShowsWhichSumItAccumulatesAndHandsThemOn) {
  // The paper's machine: the full schedule, 6 products for α, 12 for β, 10 for γ, one a cycle.
  Tmp tmp;
  const json j =
      render(tmp, "w",
             kScenes + "balls-1.nff --size 16x16 --preset paper --timing clocked --vcd " +
                 (tmp / "w.vcd") + " --vcd-window pe0+0:3000");
  ASSERT_FALSE(j.is_null());
  const std::string vcd = slurp(tmp / "w.vcd");
  const auto select = changes(vcd, "mac", "abg_select");
  const auto handed = changes(vcd, "mac", "sums_valid");
  const auto gamma = changes(vcd, "mac", "gamma");
  ASSERT_GT(select.size(), 3u) << "abg_select is not in the VCD or never changes";
  // Each α -> β -> γ run: β starts 6 cycles after α, γ 12 after β, and the sums leave with γ's
  // last product, 9 cycles after γ's first.
  int runs = 0;
  // The first entry is the value the window opened with, not a change.
  for (auto a = std::next(select.begin()); a != select.end(); ++a) {
    auto b = std::next(a);
    if (b == select.end()) break;
    auto c = std::next(b);
    if (c == select.end()) break;
    if (a->second != "0" || b->second != "1" || c->second != "10") continue;  // 0, 1, 2 in binary
    const uint64_t cycle = (b->first - a->first) / 6;
    ASSERT_GT(cycle, 0u);
    EXPECT_EQ(b->first - a->first, 6 * cycle);
    EXPECT_EQ(c->first - b->first, 12 * cycle);
    const uint64_t out = c->first + 9 * cycle;
    const auto h = handed.find(out);
    ASSERT_NE(h, handed.end()) << "no sums handed on at " << out;
    EXPECT_EQ(h->second, "1");
    ++runs;
  }
  EXPECT_GT(runs, 2) << "no complete α, β, γ accumulation seen in the window";
  // α, β, γ change only when sums are handed on (and not every time: equal sums make no change).
  ASSERT_GT(gamma.size(), 1u) << "γ never changes in the window";
  for (auto g = std::next(gamma.begin()); g != gamma.end(); ++g) {
    const auto h = handed.find(g->first);
    EXPECT_TRUE(h != handed.end() && h->second == "1")
        << "γ changed at " << g->first << " with no sums handed on";
  }
}

}  // namespace
