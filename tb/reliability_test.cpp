// Reliability of the whole program (docs/reliability.md): every accepted input finishes or is
// refused up front with exit 2, error figures that cannot lie, a checked reference cache, and
// interrupted runs that leave nothing half-written under a final name.
#include <chrono>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using namespace rtm::test;

const std::string kSpd = std::string(RTM_SOURCE_DIR) + "/scenes/spd/";

// ---- Exit codes ----

struct UsageCase {
  const char* args;
  const char* message;  ///< what stderr must name
};

// Whatever CLI11 or rtm itself finds wrong with the command line exits 2 (README), with a message
// naming the option; nothing is written.
TEST(Reliability, EveryBadCommandLineExits2NamingTheOption) {
  const std::vector<UsageCase> cases = {
      {"render --max-depth 1000000", "--max-depth"},  // CLI11's range check (its own code is 105)
      {"render --max-depth 0", "--max-depth"},
      {"render --grid 2000", "--grid"},  // 8e9 voxels (was exit 1)
      {"render --grid 4000x4000x2", "--grid"},
      {"render --size 20000x10", "--size"},  // past the 16384 a side scenes allow (was exit 1)
      {"render --pes 0", "--pes"},
      {"render --threshold 2", "--threshold"},
      {"render --threshold nan", "--threshold"},  // CLI11's range check lets NaN through
      {"render --spawn-offset nan", "--spawn-offset"},
      {"render --vcd-window 99999999999999999999999:", "--vcd-window"},  // was exit 1, "stoull"
      {"render --no-such-option", "--no-such-option"},
      {"render --pes", "--pes"},  // a missing value
      {"", "subcommand"},         // no command at all
      {"frobnicate", "subcommand"},
      // A mistyped name: the nearest one (CLI11 said "arguments were not expected", exit 109).
      {"render --pe 16", "not expected: --pe (did you mean --pes?)"},
      {"render --sizee 8x8", "(did you mean --size?)"},
      {"render --vcdwindow 1:2", "(did you mean --vcd-window?)"},
      {"rendr", "(did you mean render?)"},
      {"render --set search_unit=2",
       "search_unit: unknown machine configuration key; did you mean search_units?"},
  };
  for (const UsageCase& c : cases) {
    Tmp tmp;
    const Proc r = run_rtm(std::string(c.args) + " --out " + (tmp / "o.png") + " -q", tmp);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("rtm: ", 0), 0u) << c.args << "\n" << r.err;  // one line, rtm's
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(tmp / "o.png")) << c.args;
  }
  Tmp tmp;
  EXPECT_EQ(run_rtm("--help", tmp).exit_code, 0);
  EXPECT_EQ(run_rtm("render --help", tmp).exit_code, 0);
  EXPECT_EQ(run_rtm("--version", tmp).exit_code, 0);
}

// A grid of 4194304^3 voxels overflowed the 64-bit voxel count; it is refused as too many, naming
// the file and line (a bad scene: exit 1).
TEST(Reliability, AHugeSceneGridIsRefusedWithoutOverflow) {
  Tmp tmp;
  spit(tmp / "g.yaml",
       "camera: {eye: [0, 0, 5], look_at: [0, 0, 0], resolution: [1, 1]}\nmaterials: {m: {}}\n"
       "render: {grid: [4194304, 4194304, 4194304]}\n"
       "primitives:\n  - {sphere: {center: [0, 0, 0], radius: 1}, material: m}\n");
  const Proc r = run_rtm("render " + (tmp / "g.yaml") + " -q --out " + (tmp / "o.png"), tmp);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("g.yaml:3:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("too many voxels"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("4194304x4194304x4194304"), std::string::npos) << r.err;
}

// ---- Every accepted value works, or is refused up front ----

/// A box of six mirrors round a sphere, threshold 0: every ray is reflected until max_depth (and,
/// with `glass`, transmitted too: a tree). The camera's ray hits the sphere first.
std::string mirror_box(long max_depth, bool glass = false) {
  std::ostringstream y;
  y << "name: mirror-box\n"
       "camera: {eye: [0, 0, 0.5], look_at: [0.3, 0.2, -0.3], up: [0, 1, 0], fov: 40, resolution: "
       "[2, 2]}\n"
       "lights: [{position: [0.5, 0.8, 0.5], color: [1, 1, 1]}]\n"
       "materials:\n"
       "  mirror: {color: [1, 1, 1], ambient: 0, diffuse: 0, specular: 1}\n"
       "  ball: {color: [1, 0.5, 0.2], ambient: 0.2, diffuse: 0.8, specular: 1"
    << (glass ? ", transmission: 1, ior: 1.5" : "") << "}\n"
    << "render: {threshold: 0, max_depth: " << max_depth << "}\n"
    << "primitives:\n";
  const char* walls[] = {"[1, 0, 0], d: 1, box: {min: [-1.1, -1.1, -1.1], max: [-0.9, 1.1, 1.1]}",
                         "[-1, 0, 0], d: 1, box: {min: [0.9, -1.1, -1.1], max: [1.1, 1.1, 1.1]}",
                         "[0, 1, 0], d: 1, box: {min: [-1.1, -1.1, -1.1], max: [1.1, -0.9, 1.1]}",
                         "[0, -1, 0], d: 1, box: {min: [-1.1, 0.9, -1.1], max: [1.1, 1.1, 1.1]}",
                         "[0, 0, 1], d: 1, box: {min: [-1.1, -1.1, -1.1], max: [1.1, 1.1, -0.9]}",
                         "[0, 0, -1], d: 1, box: {min: [-1.1, -1.1, 0.9], max: [1.1, 1.1, 1.1]}"};
  for (const char* w : walls) y << "  - {plane: {normal: " << w << "}, material: mirror}\n";
  y << "  - {sphere: {center: [0.3, 0.2, -0.3], radius: 0.3}, material: ball}\n";
  return y.str();
}

/// rtm under `timeout`: a run that would never finish fails the test (exit 124) instead of hanging
/// it.
Proc run_rtm_within(int seconds, const std::string& args, const Tmp& tmp) {
  return sh("timeout " + std::to_string(seconds) + " " + std::string(RTM_BINARY) + " " + args, tmp);
}

// Ray::depth is 8 bits: at max_depth 256 a mirror box's rays wrapped round to depth 0 and were
// reflected for ever, and at 2^31 - 1 the scene analysis itself looped. 255 is the largest
// accepted.
TEST(Reliability, TheMirrorBoxFinishesAtTheDeepestAcceptedDepthAndBeyondItIsRefused) {
  Tmp tmp;
  spit(tmp / "box255.yaml", mirror_box(255));
  const auto t0 = std::chrono::steady_clock::now();
  const Proc ok =
      run_rtm_within(60, "render " + (tmp / "box255.yaml") + " -q --out " + (tmp / "o.png"), tmp);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const json j = json::parse(slurp(tmp / "o.json"));
  EXPECT_EQ(j["left_out"]["scene_needs"]["deepest_generation"], 255);
  EXPECT_GT(j["rays"]["reflected"].get<uint64_t>(), 4u * 250)
      << "every pixel's ray is reflected to the last generation";
  EXPECT_LT(seconds, 30);
  for (long depth : {256L, 1000L, 2147483647L}) {
    spit(tmp / "box.yaml", mirror_box(depth));
    const Proc r =
        run_rtm_within(20, "render " + (tmp / "box.yaml") + " -q --out " + (tmp / "x.png"), tmp);
    EXPECT_EQ(r.exit_code, 1) << depth << ": a bad scene\n" << r.err;
    EXPECT_NE(r.err.find("box.yaml:7:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("max_depth must be in 1..255"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("got " + std::to_string(depth)), std::string::npos) << r.err;
  }
  const Proc flag = run_rtm_within(
      20, "render " + (tmp / "box255.yaml") + " --max-depth 256 -q --out " + (tmp / "x.png"), tmp);
  EXPECT_EQ(flag.exit_code, 2) << flag.err;
  EXPECT_NE(flag.err.find("--max-depth"), std::string::npos) << flag.err;
  EXPECT_NE(flag.err.find("256"), std::string::npos) << flag.err;
  EXPECT_FALSE(fs::exists(tmp / "x.png"));
}

/// Each number key's range as `rtm config` prints it ("(an integer in 1..16384)"): the test follows
/// the declarations, so a new key is covered as soon as it is declared.
struct KeyRange {
  std::string min, max;
};
std::map<std::string, KeyRange> key_ranges(const Tmp& tmp) {
  const Proc r = run_rtm("config", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::map<std::string, KeyRange> ranges;
  const std::regex line(
      R"(^(\w+): \S+ +# .*\((?:an integer|a number) in ([-0-9.e+]+)\.\.([-0-9.e+]+)(?:, a multiple of [0-9.e+-]+)?\)$)");
  std::istringstream in(r.out);
  for (std::string l; std::getline(in, l);) {
    std::smatch m;
    if (std::regex_match(l, m, line)) ranges[m[1]] = {m[2], m[3]};
  }
  return ranges;
}

/// The value one step past an end: the next integer, or for a number 1% beyond (or below 0).
std::string past(const std::string& end, bool above, bool integer) {
  if (integer) return std::to_string(std::stol(end) + (above ? 1 : -1));
  const double x = std::stod(end);
  std::ostringstream s;
  s.precision(17);
  s << (above ? x * 1.01 : x == 0 ? -0.001 : x * 0.99);
  return s.str();
}

// One past either end of every key is refused naming the key, the value and the range, exit 2;
// so are the values the issue found hanging or overflowing.
TEST(Reliability, OnePastEitherEndOfEveryKeyIsRefusedNamingKeyValueAndRange) {
  Tmp tmp;
  const auto ranges = key_ranges(tmp);
  ASSERT_GE(ranges.size(), 30u);
  std::vector<std::pair<std::string, std::string>> refused;
  for (const auto& [key, r] : ranges) {
    const bool integer = r.min.find_first_of(".e") == std::string::npos &&
                         r.max.find_first_of(".e") == std::string::npos;
    refused.push_back({key, past(r.min, false, integer)});
    refused.push_back({key, past(r.max, true, integer)});
  }
  for (const char* kv :
       {"clock_ns=1e-300", "clock_ns=1e300", "host_clock_ns=1e300", "link_bandwidth_mb_s=1e-300",
        "link_latency_ns=1e300", "mul_latency=1073741824", "mul_latency=2147483647",
        "search_fifo_depth=2147483647", "clock_ns=0.0015"}) {
    const std::string s(kv);
    refused.push_back({s.substr(0, s.find('=')), s.substr(s.find('=') + 1)});
  }
  for (const auto& [key, value] : refused) {
    const Proc r = run_rtm("config --set " + key + "=" + value, tmp);
    EXPECT_EQ(r.exit_code, 2) << key << "=" << value;
    EXPECT_NE(r.err.find(key + ": expected "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("got " + value), std::string::npos) << r.err;
    if (ranges.count(key)) {
      EXPECT_NE(r.err.find(" in " + ranges.at(key).min + ".." + ranges.at(key).max),
                std::string::npos)
          << r.err;
    }
  }
  // rtm render reads the same declarations.
  const Proc r = run_rtm("render --set mul_latency=2147483647 -q --out " + (tmp / "o.png"), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("mul_latency: expected an integer in 1..1024, got 2147483647"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(tmp / "o.png"));
}

/// `--set key=value` for every key at one end of its range (`pes` left out: its own test).
std::string every_key_at(const std::map<std::string, KeyRange>& ranges, bool max,
                         const std::map<std::string, std::string>& except = {}) {
  std::string args;
  for (const auto& [key, r] : ranges) {
    if (key == "pes") continue;
    const auto e = except.find(key);
    args += " --set " + key + "=" + (e != except.end() ? e->second : max ? r.max : r.min);
  }
  return args;
}

// Every key at the low end of its range in one frame, then every key at the high end, in fast
// timing; in clocked timing the ends that change it (the clock, the MAC latencies, the lanes),
// which must give the fast timing's cycles. Each finishes in seconds, matching the reference.
TEST(Reliability, EveryKeyAtEitherEndOfItsRangeRendersAFrame) {
  Tmp tmp;
  const auto ranges = key_ranges(tmp);
  const std::string scene = kSpd + "balls-1.nff --size 2x2";
  auto frame = [&](const std::string& name, const std::string& args) {
    const Proc r =
        run_rtm_within(60, "render " + scene + args + " -q --out " + (tmp / (name + ".png")), tmp);
    EXPECT_EQ(r.exit_code, 0) << name << "\n" << r.err;
    if (r.exit_code != 0) return json();
    const json j = json::parse(slurp(tmp / (name + ".json")));
    EXPECT_EQ(j["error"]["pixels_over_1_255"], 0) << name;
    EXPECT_GT(j["cycles"].get<uint64_t>(), 0u) << name;
    return j;
  };
  const json defaults = frame("defaults", "");
  // The smallest local memory holds no real scene: its refusal has its own test
  // (Cli.LocalMemoryIsLaidOutReportedAndTooSmallAMemoryIsRefused).
  const std::map<std::string, std::string> memory{
      {"local_memory_bytes", ranges.at("local_memory_bytes").max}};
  const json low = frame("low", every_key_at(ranges, false, memory));
  // Several frames refuse streamed rays (ray_block at its end): the most frames run on their own.
  const json high = frame("high", every_key_at(ranges, true, {{"frames", "1"}}));
  const json most_frames = frame("most-frames", " --frames " + ranges.at("frames").max);
  // The clocked MAC steps every cycle: its low end with the fast link (the slow one is the
  // low end above), its high end with the MAC's own keys and the lanes at their maxima.
  const json clocked_low = frame(
      "clocked-low", every_key_at(ranges, false,
                                  {{"link_bandwidth_mb_s", ranges.at("link_bandwidth_mb_s").max},
                                   *memory.begin()}) +
                         " --timing clocked");
  const std::string mac_high = " --set mul_latency=" + ranges.at("mul_latency").max +
                               " --set add_latency=" + ranges.at("add_latency").max +
                               " --set clock_ns=" + ranges.at("clock_ns").max +
                               " --set intersection_units=" + ranges.at("intersection_units").max +
                               " --set search_units=" + ranges.at("search_units").max;
  const json clocked_high = frame("clocked-high", mac_high + " --timing clocked");
  const json fast_high = frame("fast-high", mac_high);
  ASSERT_FALSE(defaults.is_null() || high.is_null() || clocked_high.is_null() ||
               fast_high.is_null() || most_frames.is_null());
  EXPECT_EQ(std::to_string(most_frames["frames"]["count"].get<int>()), ranges.at("frames").max);
  EXPECT_GT(high["cycles"].get<uint64_t>(), defaults["cycles"].get<uint64_t>());
  EXPECT_EQ(clocked_high["cycles"], fast_high["cycles"]);
  EXPECT_EQ(clocked_high["mac"], fast_high["mac"]);
}

// mul_latency = 2^31 - 1 once overflowed the MAC's pipeline depth and reported fewer cycles than
// the default; at its largest accepted value every MAC job takes longer, so the frame does.
TEST(Reliability, TheLongestMacLatencyGivesMoreCyclesNotFewer) {
  Tmp tmp;
  const std::string scene = kSpd + "balls-1.nff --size 4x4";
  const json base = render(tmp, "base", scene);
  const json slow = render(tmp, "slow", scene + " --set mul_latency=1024");
  ASSERT_FALSE(base.is_null() || slow.is_null());
  // Each test's α, β, γ leave the adder 2 · 1023 cycles later than at latency 1.
  EXPECT_GE(slow["mac"]["busy_cycles"].get<uint64_t>(),
            base["mac"]["busy_cycles"].get<uint64_t>() +
                2 * 1023 * base["intersection_tests"].get<uint64_t>() / 28);
  EXPECT_GT(slow["cycles"].get<uint64_t>(), base["cycles"].get<uint64_t>());
}

// The documented maximum of PEs runs (one SystemC thread each on the PE engine); one more is
// refused. With one thread per unit (pe_simulation = modules) as many PEs would need more memory
// maps than the host allows: refused before elaborating, naming the limit.
TEST(Reliability, TheMostPesRunAndMoreThreadsThanTheHostAllowsAreRefusedUpFront) {
  Tmp tmp;
  const std::string args = "render " + kSpd + "balls-1.nff --size 1x1 -q";
#ifdef __SANITIZE_THREAD__
  // ThreadSanitizer maps memory of its own for every thread SystemC starts, beyond what rtm counts
  // against vm.max_map_count: at 16384 PEs it failed to mmap (error 12) under the default limit.
  const int pes = 8192;
#else
  const int pes = 16384;
#endif
  const Proc most = run_rtm_within(
      120, args + " --pes " + std::to_string(pes) + " --out " + (tmp / "o.png"), tmp);
  ASSERT_EQ(most.exit_code, 0) << most.err;
  const json j = json::parse(slurp(tmp / "o.json"));
  EXPECT_EQ(j["per_pe"].size(), size_t(pes));
  EXPECT_TRUE(j["pe_simulation"]["engine"].get<bool>());
  const Proc more = run_rtm(args + " --pes 16385 --out " + (tmp / "x.png"), tmp);
  EXPECT_EQ(more.exit_code, 2);
  EXPECT_NE(more.err.find("pes: expected an integer in 1..16384, got 16385"), std::string::npos)
      << more.err;
  long limit = 0;
  std::ifstream("/proc/sys/vm/max_map_count") >> limit;
  if (limit <= 0 || limit > 2 * 8 * 16384 + 10000)
    GTEST_SKIP() << "this host maps enough threads for 16384 modules PEs";
  const auto t0 = std::chrono::steady_clock::now();
  const Proc modules =
      run_rtm(args + " --pes 16384 --set pe_simulation=modules --out " + (tmp / "x.png"), tmp);
  EXPECT_EQ(modules.exit_code, 2) << modules.err;
  EXPECT_NE(modules.err.find("vm.max_map_count"), std::string::npos) << modules.err;
  EXPECT_NE(modules.err.find("pes: 16384 PEs need"), std::string::npos) << modules.err;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10)
      << "refused up front";
  EXPECT_FALSE(fs::exists(tmp / "x.png"));
}

// ---- The reference cache ----

/// rtm with its own cache folder (and optionally a size cap).
Proc run_cached(const Tmp& tmp, const std::string& args, const std::string& env = "") {
  return sh(
      "RTM_CACHE_DIR=" + (tmp / "cache") + " " + env + " " + std::string(RTM_BINARY) + " " + args,
      tmp);
}

std::vector<fs::path> cache_entries(const Tmp& tmp) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(tmp / "cache", ec))
    if (e.path().extension() == ".ref" && e.path().filename().string()[0] != '.')
      out.push_back(e.path());
  return out;
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The issue's case: 64 flipped bytes in a cache entry once gave cached: true, rmse null, psnr "inf"
// and 5 pixels off. Now a damaged, truncated or mismatched entry is reported once, deleted and
// rendered again, and the figures are the undamaged run's.
TEST(Reliability, ADamagedCacheEntryIsReportedOnceDeletedAndRenderedAgain) {
  Tmp tmp;
  const std::string frame =
      "render " + kSpd + "rings-1.nff --pes 2 --size 32x32 -q --out " + (tmp / "o.png");
  auto figures = [&](const std::string& extra = "") {
    const Proc r = run_cached(tmp, frame + extra);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    json j = r.exit_code == 0 ? json::parse(slurp(tmp / "o.json")) : json();
    j["stderr"] = r.err;
    return j;
  };
  const json first = figures();
  ASSERT_EQ(first["reference"]["cached"], false);
  const std::vector<fs::path> entries = cache_entries(tmp);
  ASSERT_EQ(entries.size(), 1u);
  const fs::path entry = entries[0];
  const std::string good = slurp(entry.string());

  auto damaged = [&](const std::string& bytes, const std::string& why) {
    spit(entry.string(), bytes);
    const json again = figures();
    EXPECT_EQ(again["reference"]["cached"], false) << why;
    EXPECT_EQ(count(again["stderr"], "rtm: reference cache: "), 1u) << again["stderr"];
    EXPECT_NE(again["stderr"].get<std::string>().find(why), std::string::npos) << again["stderr"];
    EXPECT_EQ(again["error"], first["error"]) << why;
    EXPECT_EQ(again["reference"]["counts_match"], first["reference"]["counts_match"]) << why;
    // Stored again whole: the next run takes it, silently.
    const json third = figures();
    EXPECT_EQ(third["reference"]["cached"], true) << why;
    EXPECT_EQ(third["stderr"], "") << why;
    EXPECT_EQ(third["error"], first["error"]) << why;
    EXPECT_EQ(slurp(entry.string()).size(), good.size());
  };
  std::string flipped = good;
  for (size_t i = 0; i < 64; ++i)
    flipped[flipped.size() / 2 + i] = char(~flipped[flipped.size() / 2 + i]);
  damaged(flipped, "is damaged (its checksum does not match its contents)");
  damaged(good.substr(0, good.size() - 100), "bytes, not the " + std::to_string(good.size()));
  // Another setting's entry, whole and valid, under this key's name.
  const json other = figures(" --threshold 0.5");
  ASSERT_EQ(cache_entries(tmp).size(), 2u);
  for (const fs::path& e : cache_entries(tmp))
    if (e != entry) damaged(slurp(e.string()), "was made for another scene or setting");
}

// Two runs filling the same entry at once (two sweeps) both succeed and leave one whole entry and
// no temporaries; the size cap evicts the least recently used entries and never stores one larger
// than itself; `rtm cache info|clean` report and empty the cache; temporaries of writers that are
// gone are removed, those of running writers kept.
TEST(Reliability, TheCacheIsSafeForConcurrentWritersCappedAndCleaned) {
  Tmp tmp;
  const std::string frame = "render " + kSpd + "balls-1.nff --size 24x24 -q";
  const std::string rtm =
      "RTM_CACHE_DIR=" + (tmp / "cache") + " " + std::string(RTM_BINARY) + " " + frame;
  const Proc both = sh("(" + rtm + " --out " + (tmp / "a.png") + " & " + rtm + " --out " +
                           (tmp / "b.png") + " & wait %1 && wait %2)",
                       tmp);
  EXPECT_EQ(both.exit_code, 0) << both.err;
  EXPECT_EQ(both.err, "");
  ASSERT_EQ(cache_entries(tmp).size(), 1u);
  const uint64_t entry_bytes = fs::file_size(cache_entries(tmp)[0]);
  for (const auto& e : fs::directory_iterator(tmp / "cache"))
    EXPECT_EQ(e.path().filename().string().find("partial"), std::string::npos) << e.path();
  const Proc hit = run_cached(tmp, frame + " --out " + (tmp / "c.png"));
  EXPECT_EQ(json::parse(slurp(tmp / "c.json"))["reference"]["cached"], true) << hit.err;

  // A cap of 1.5 entries: each new entry evicts the older one.
  const std::string cap = "RTM_CACHE_SIZE=" + std::to_string(entry_bytes * 3 / 2);
  for (const char* t : {"0.1", "0.2"})
    EXPECT_EQ(
        run_cached(tmp, frame + " --threshold " + t + " --out " + (tmp / "d.png"), cap).exit_code,
        0);
  ASSERT_EQ(cache_entries(tmp).size(), 1u);
  EXPECT_EQ(run_cached(tmp, frame + " --threshold 0.2 --out " + (tmp / "d.png"), cap).exit_code, 0);
  EXPECT_EQ(json::parse(slurp(tmp / "d.json"))["reference"]["cached"], true)
      << "the last one stored is kept";
  EXPECT_EQ(
      run_cached(tmp, frame + " --threshold 0.3 --out " + (tmp / "d.png"), "RTM_CACHE_SIZE=1K")
          .exit_code,
      0);
  EXPECT_EQ(cache_entries(tmp).size(), 1u) << "an entry larger than the cap is not stored";

  // Temporaries: a dead writer's on this host, a running one's (this test), another host's old and
  // new.
  const Proc dead = sh("sh -c 'echo $$'", tmp);
  const std::string host = [] {
    char h[256] = "";
    gethostname(h, sizeof h - 1);
    return std::string(h);
  }();
  const std::string dead_tmp =
      tmp / ("cache/.x.partial-" + host + "-" + std::to_string(std::stol(dead.out)) + ".ref");
  const std::string live_tmp =
      tmp / ("cache/.y.partial-" + host + "-" + std::to_string(getpid()) + ".ref");
  const std::string old_tmp = tmp / "cache/.z.partial-elsewhere-12.ref",
                    new_tmp = tmp / "cache/.w.partial-elsewhere-13.ref";
  for (const std::string& f : {dead_tmp, live_tmp, old_tmp, new_tmp}) spit(f, "partial");
  fs::last_write_time(old_tmp, fs::file_time_type::clock::now() - std::chrono::hours(48));
  const Proc info = run_cached(tmp, "cache info");
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("entries: 1, "), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("partial files: 4 (2 left by writers that are gone)"), std::string::npos)
      << info.out;
  const Proc clean = run_cached(tmp, "cache clean");
  EXPECT_EQ(clean.exit_code, 0) << clean.err;
  EXPECT_NE(clean.out.find("removed 1 entry ("), std::string::npos) << clean.out;
  EXPECT_NE(clean.out.find(") and 2 partial files from "), std::string::npos) << clean.out;
  EXPECT_TRUE(cache_entries(tmp).empty());
  EXPECT_FALSE(fs::exists(dead_tmp));
  EXPECT_FALSE(fs::exists(old_tmp));
  EXPECT_TRUE(fs::exists(live_tmp));
  EXPECT_TRUE(fs::exists(new_tmp));
  EXPECT_EQ(run_cached(tmp, "cache frobnicate").exit_code, 2);
}

// ---- Interruption ----

/// Starts rtm with `args` (split at spaces), stdout and stderr into `log`; returns its PID.
pid_t start_rtm(const std::string& args, const std::string& log) {
  std::vector<std::string> words{RTM_BINARY};
  std::istringstream in(args);
  for (std::string w; in >> w;) words.push_back(w);
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    if (!freopen(log.c_str(), "w", stdout) || !freopen(log.c_str(), "a", stderr)) _exit(127);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

/// The names in a folder.
std::vector<std::string> names_in(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) out.push_back(e.path().filename().string());
  return out;
}

/// Waits (up to a minute) until rtm is writing its waveform's temporary, then a little longer.
bool wait_for_partial(const std::string& dir) {
  for (int i = 0; i < 600; ++i) {
    for (const std::string& n : names_in(dir))
      if (n.find(".partial-") != std::string::npos) {
        usleep(300 * 1000);
        return true;
      }
    usleep(100 * 1000);
  }
  return false;
}

// SIGINT or SIGTERM in the middle of a clocked render writing a waveform: rtm removes its
// temporaries and dies of the signal (a shell reports 130 or 143). Nothing is left under a final
// name, and the earlier run's outputs at the same paths were removed when this one began.
// SIGKILL cannot be caught: it leaves only the temporary, named as partial, which the next run
// writing the same waveform removes.
TEST(Reliability, AnInterruptedRenderLeavesNoFinalNamedPartialFile) {
  Tmp tmp;
  const std::string out = tmp / "out";
  const std::string args =
      "render " + kSpd + "balls-1.nff --size 256x256 --timing clocked -q --vcd " + out +
      "/w.vcd --vcd-window 0:2000 --out " + out + "/o.png --id-map " + out + "/id.exr";
  for (int sig : {SIGINT, SIGTERM, SIGKILL}) {
    fs::create_directories(out);
    for (const char* old : {"o.png", "o.json", "id.exr", "w.vcd", "w.gtkw"})
      spit(out + "/" + old, "an earlier run's");
    const pid_t pid = start_rtm(args, tmp / "log.txt");
    ASSERT_TRUE(wait_for_partial(out))
        << sig << ": no waveform being written; " << slurp(tmp / "log.txt");
    kill(pid, sig);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status))
        << sig << ": exit " << WEXITSTATUS(status) << "; " << slurp(tmp / "log.txt");
    EXPECT_EQ(WTERMSIG(status), sig);
    const std::vector<std::string> left = names_in(out);
    if (sig == SIGKILL) {
      ASSERT_EQ(left.size(), 1u) << "only the temporary the kill interrupted";
      EXPECT_EQ(left[0].rfind(".w.partial-", 0), 0u) << left[0];
    } else {
      EXPECT_TRUE(left.empty()) << sig << ": " << left.size() << " files left, the first "
                                << left[0];
      EXPECT_NE(slurp(tmp / "log.txt")
                    .find(sig == SIGINT
                              ? "rtm: interrupted (SIGINT); its partial output files are removed"
                              : "rtm: terminated (SIGTERM); its partial output files are removed"),
                std::string::npos)
          << slurp(tmp / "log.txt");
    }
  }
  // The next run writing the same waveform removes the abandoned temporary and writes it whole;
  // a waveform's folder is made as an image's is.
  const Proc fresh =
      run_rtm("render " + kSpd + "balls-1.nff --size 2x2 --timing clocked -q --vcd " +
                  (tmp / "new/w.vcd") + " --out " + (tmp / "new2/o.png"),
              tmp);
  EXPECT_EQ(fresh.exit_code, 0) << fresh.err;
  EXPECT_TRUE(fs::exists(tmp / "new/w.vcd"));
  const Proc again =
      run_rtm("render " + kSpd + "balls-1.nff --size 8x8 --timing clocked -q --vcd " + out +
                  "/w.vcd --out " + out + "/o.png",
              tmp);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  std::vector<std::string> left = names_in(out);
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"o.json", "o.png", "w.gtkw", "w.vcd"}));
  EXPECT_NE(slurp(out + "/w.vcd").find("$enddefinitions"), std::string::npos);
}

// ---- The memory budget ----

// A 16384x16384 frame (the largest a scene may ask for) once reached 12 GB as a reference render
// and was OOM-killed as a machine render. Below what it needs it is refused before anything
// frame-sized is allocated, naming the part that is too big; exit 2, nothing written.
TEST(Reliability, TheMemoryBudgetRefusesTheLargestFrameBelowWhatItNeeds) {
  Tmp tmp;
  const std::string scene = kSpd + "balls-1.nff --size 16384x16384 -q --out " + (tmp / "o.png");
  struct Case {
    std::string args, part;
  };
  for (const Case& c :
       {Case{" --reference --max-memory 4G", "the largest part is the image: "},
        Case{" --max-memory 16G", "the largest part is the primary rays: "},
        Case{" --pes 64 --max-memory 512M", "the largest part is the primary rays: "}}) {
    const auto t0 = std::chrono::steady_clock::now();
    const Proc r = run_rtm_within(60, "render " + scene + c.args, tmp);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find("--max-memory: this render needs about "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.part), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("16384x16384 pixels"), std::string::npos) << r.err;
    // Up front: about 2 s of CPU (the grid), against minutes and tens of GB for the render; 30 s
    // of wall time leaves room for a shared machine (14 s measured at a load average of 9).
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30)
        << "refused up front";
    EXPECT_FALSE(fs::exists(tmp / "o.png"));
  }
  // The default budget is a share of this machine's memory; an NFF asking for the largest frame
  // exceeds it on any machine with less than about 127 GiB.
  spit(tmp / "big.nff",
       "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 16384 16384\n"
       "f 1 0 0 1 0 1 0 1\ns 0 0 0 1\n");
  const Proc nff =
      run_rtm_within(60, "render " + (tmp / "big.nff") + " -q --out " + (tmp / "o.png"), tmp);
  if (sysconf(_SC_PHYS_PAGES) * double(sysconf(_SC_PAGESIZE)) < 100.0 * (1ull << 30)) {
    EXPECT_EQ(nff.exit_code, 2) << nff.err;
    EXPECT_NE(nff.err.find("(the default, 3/4 of the "), std::string::npos) << nff.err;
  }
  for (const char* bad : {"12Q", "0", "-1G", "G"}) {
    const Proc r = run_rtm(
        "render --size 4x4 -q --max-memory " + std::string(bad) + " --out " + (tmp / "o.png"), tmp);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("--max-memory: expected a size such as 512M or 4G"), std::string::npos)
        << r.err;
  }
  const Proc fits = run_rtm(
      "render " + kSpd + "balls-1.nff --size 16x16 -q --max-memory 1G --out " + (tmp / "o.png"),
      tmp);
  EXPECT_EQ(fits.exit_code, 0) << fits.err;
}

/// The glass box of one pixel: its tree grows without a bound any render could reach.
std::string glass_box() {
  std::string box = mirror_box(255, true);
  return box.replace(box.find("resolution: [2, 2]"), 18, "resolution: [1, 1]");
}

/// rtm on a terminal (a pseudo-terminal of `script`, so that it draws its progress line) for at
/// most `seconds`; what the terminal showed.
std::string on_a_terminal(int seconds, const std::string& args, const Tmp& tmp) {
  return sh("timeout -k 5 " + std::to_string(seconds) + " script -qfec '" +
                std::string(RTM_BINARY) + " " + args + "' /dev/null",
            tmp)
      .out;
}

// Within the command line's limits a box of mirrors round a transmitting sphere, threshold 0,
// max_depth 255, grows its ray tree without a bound a render could reach. rtm says so before it
// starts, and stops the simulation once the rays waiting in the front buffers outgrow the budget.
TEST(Reliability, ARayTreeThatGrowsWithoutBoundIsStoppedAtTheMemoryBudget) {
  Tmp tmp;
  spit(tmp / "glass.yaml", glass_box());
  const Proc r = run_rtm_within(
      60, "render " + (tmp / "glass.yaml") + " -q --max-memory 220M --out " + (tmp / "o.png"), tmp);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("rtm: note: one primary ray can grow into up to 1.16e+77 rays (max_depth "
                       "255, threshold 0)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("more than its memory budget of 220.0 MiB (--max-memory)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("rays waiting in the front buffers grow with the ray tree"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(tmp / "o.png"));
  EXPECT_FALSE(fs::exists(tmp / "o.json"));
  // The mirrors alone make one ray a generation: no note.
  spit(tmp / "mirrors.yaml", mirror_box(255));
  const Proc m =
      run_rtm_within(60, "render " + (tmp / "mirrors.yaml") + " -q --out " + (tmp / "o.png"), tmp);
  EXPECT_EQ(m.exit_code, 0) << m.err;
  EXPECT_EQ(m.err.find("note:"), std::string::npos) << m.err;
}

// The reference renderer traces each pixel's tree depth first, so the glass box holds little
// memory there, but never ends: it shows its progress on a terminal (the rays still counting
// while the pixel does not finish) and stops at the work budget, exit 1, nothing written. The
// machine's simulation stops at the same budget.
TEST(Reliability, TheReferenceShowsProgressAndStopsAtTheWorkBudgetAsTheMachineDoes) {
  Tmp tmp;
  spit(tmp / "glass.yaml", glass_box());
  const std::string glass = "render " + (tmp / "glass.yaml") + " --out " + (tmp / "o.png");
  const std::string note =
      "rtm: note: one primary ray can grow into up to 1.16e+77 rays (max_depth 255, threshold 0): "
      "the render may not "
      "finish; it stops if its ray trees ";
  const Proc r = run_rtm_within(60, glass + " --reference -q --max-rays 5e5", tmp);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err, note +
                       "pass --max-rays, and Ctrl-C stops it cleanly\n"
                       "rtm: the reference render stopped at its work budget of 500000 rays "
                       "(--max-rays), with 0 of 1 "
                       "pixels done: the ray trees grow with max_depth 255 and threshold 0\n");
  EXPECT_FALSE(fs::exists(tmp / "o.png"));
  EXPECT_FALSE(fs::exists(tmp / "o.json"));
  for (const char* order : {"ranked", "kernel"}) {
    const Proc m = run_rtm_within(60, glass + " -q --max-rays 2e4 --set arbitration=" + order, tmp);
    EXPECT_EQ(m.exit_code, 1) << order << "\n" << m.err;
    EXPECT_NE(m.err.find(note + "outgrow --max-memory or pass --max-rays"), std::string::npos)
        << m.err;
    EXPECT_NE(
        m.err.find(
            "rtm: the simulation stopped at its work budget of 20000 rays (--max-rays), at cycle "),
        std::string::npos)
        << order << "\n"
        << m.err;
    EXPECT_FALSE(fs::exists(tmp / "o.png"));
  }
  // Drawn after the first second, redrawn twice a second: 4 s show it.
  const std::string shown = on_a_terminal(4, glass + " --reference", tmp);
  EXPECT_NE(shown.find("\rreference: at pixel 0/1 (0.0%), "), std::string::npos) << shown;
  EXPECT_TRUE(std::regex_search(shown, std::regex(R"(, [0-9.e+]+ rays, [0-9.]+ GiB)"))) << shown;
  for (const char* bad : {"0", "-5", "many"}) {
    const Proc b = run_rtm(glass + " -q --max-rays " + bad, tmp);
    EXPECT_EQ(b.exit_code, 2) << bad << "\n" << b.err;
    EXPECT_NE(b.err.find("--max-rays"), std::string::npos) << b.err;
  }
}

// With arbitration = kernel a monitor process would change SystemC's same-time order, and so the
// figures; the monitor watches from outside the kernel instead, between slices of the
// simulation. So a kernel-order run without a progress line is held to its budgets (the work
// budget above) and its stalls are found, and its figures are the same whether a progress line
// is drawn or not (they were not: the monitor ran only with the line).
TEST(Reliability, WithKernelArbitrationTheMonitorWatchesWithoutChangingTheFigures) {
  Tmp tmp;
  // Without credits tiny FIFOs deadlock; the clock keeps such a simulation going, so only the
  // monitor can find it.
  const Proc d = run_rtm_within(
      60,
      "render " + kSpd +
          "balls-1.nff --size 24x24 --timing clocked --set arbitration=kernel"
          " --set flow_control=none --set search_fifo_depth=1 --set intersect_fifo_depth=1"
          " --set feedback_fifo_depth=1 --set shade_fifo_depth=1 --set root_fifo_depth=1 -q "
          "--out " +
          (tmp / "d.png"),
      tmp);
  EXPECT_EQ(d.exit_code, 3) << d.err;
  EXPECT_NE(d.err.find("deadlock"), std::string::npos) << d.err;
  // The golden case ModulesKernelArbitration, quiet and on a terminal.
  const std::string kernel = "render " + kSpd +
                             "balls-2.nff --size 32x32 --pes 2 --set pe_simulation=modules --set "
                             "arbitration=kernel --out ";
  const Proc quiet = run_rtm_within(60, kernel + (tmp / "q.png") + " -q", tmp);
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  on_a_terminal(60, kernel + (tmp / "t.png"), tmp);
  ASSERT_TRUE(fs::exists(tmp / "t.json"));
  const json q = json::parse(slurp(tmp / "q.json")), t = json::parse(slurp(tmp / "t.json"));
  for (const char* figure : {"cycles", "per_pe", "fifo", "mac", "rays", "utilisation", "phases"})
    EXPECT_EQ(q[figure], t[figure]) << figure;
}

}  // namespace
