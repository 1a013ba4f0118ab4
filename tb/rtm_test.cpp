// Whole-program tests: run the rtm executable and check what it writes and says.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>
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

json stats(const std::string& path) { return json::parse(slurp(path)); }

double id_agreement(const std::string& a, const std::string& b) {
  const rtm::Image x = rtm::read_id_map(a), y = rtm::read_id_map(b);
  size_t same = 0;
  for (size_t i = 0; i < x.ids.size(); ++i) same += x.ids[i] == y.ids[i];
  return double(same) / double(x.ids.size());
}

TEST(Cli, HelpListsTheCommands) {
  Tmp tmp;
  const Proc r = run_rtm("--help", tmp);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("render"), std::string::npos);
  EXPECT_NE(r.out.find("config"), std::string::npos);
}

TEST(Cli, ReferenceRenderOfTheDefaultSceneWritesImageStatsAndIdMap) {
  Tmp tmp;
  const Proc r = run_rtm(
      "render --reference --size 40x30 --out " + (tmp / "d.png") + " --id-map " + (tmp / "id.exr"),
      tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(tmp / "d.png"), std::string::npos)
      << "the summary says where the image went";
  const json j = stats(tmp / "d.json");
  EXPECT_EQ(j["scene"], "default");
  EXPECT_EQ(j["width"], 40);
  EXPECT_EQ(j["height"], 30);
  EXPECT_GT(j["wall_seconds"].get<double>(), 0);
  EXPECT_EQ(j["rays"]["primary"], 1200);
  for (const char* k : {"shadow", "reflected", "transmitted"})
    EXPECT_GT(j["rays"][k].get<int>(), 0) << k;
  EXPECT_GT(j["voxel_steps"].get<int>(), 0);
  EXPECT_GT(j["intersection_tests"].get<int>(), 0);
  const rtm::Image img = rtm::read_image(tmp / "d.png");
  EXPECT_EQ(img.width, 40);
  const rtm::Image ids = rtm::read_id_map(tmp / "id.exr");
  int background = 0, hit = 0;
  for (int32_t id : ids.ids) (id < 0 ? background : hit)++;
  EXPECT_GT(background, 0);
  EXPECT_GT(hit, 0);
}

// On its own the reference sizes its automatic grid for a CPU (finer than the machine's on a
// "teapot in a stadium"); `--grid machine` gives it the machine's. The picture does not depend on
// it.
TEST(Cli, ReferenceUsesACpuGridUnlessAskedForTheMachines) {
  Tmp tmp;
  const std::string scene = kScenes + "tree-3.nff --size 32x32";
  const json cpu = render(tmp, "cpu", scene + " --reference");
  const json machine_grid = render(tmp, "mg", scene + " --reference --grid machine");
  const json machine = render(tmp, "m", scene + " --pes 1");
  ASSERT_FALSE(cpu.is_null() || machine_grid.is_null() || machine.is_null());
  EXPECT_EQ(machine_grid["grid"]["resolution"], machine["grid"]["resolution"]);
  EXPECT_GT(cpu["grid"]["resolution"][0].get<int>(), machine["grid"]["resolution"][0].get<int>());
  EXPECT_EQ(machine_grid["voxel_steps"], machine["voxel_steps"]);
  EXPECT_EQ(rtm::read_image(tmp / "cpu.exr").rgb, rtm::read_image(tmp / "mg.exr").rgb);
  EXPECT_EQ(rtm::read_id_map(tmp / "cpu-id.exr").ids, rtm::read_id_map(tmp / "mg-id.exr").ids);
}

TEST(Cli, MachineStatsHaveEveryDocumentedKey) {
  Tmp tmp;
  const json j = render(tmp, "m", kScenes + "balls-1.nff --size 24x24 --pes 2");
  ASSERT_FALSE(j.is_null());
  for (const char* k : {"scene", "width", "height", "rays", "voxel_steps", "intersection_tests",
                        "wall_seconds", "pes", "timing", "precision", "cycles", "sim_time_ns",
                        "mac", "per_pe", "fifo", "error", "utilisation", "preset", "config"})
    EXPECT_TRUE(j.contains(k)) << k;
  for (const char* k : {"rmse", "psnr_db", "max_abs", "pixels_over_1_255", "primary_ids_differing"})
    EXPECT_TRUE(j["error"].contains(k)) << k;
  EXPECT_EQ(j["per_pe"].size(), 2u);
  for (const json& pe : j["per_pe"]) {
    EXPECT_GT(pe["cycles"].get<uint64_t>(), 0u);
    EXPECT_GT(pe["rays"].get<uint64_t>(), 0u);
    EXPECT_TRUE(pe["busy_cycles"].contains("mac"));
  }
  // The sparse schedule (the default) skips zero coefficients; what it skipped plus what it ran is
  // the paper's 28.
  EXPECT_EQ(
      j["mac"]["products"].get<uint64_t>() + j["left_out"]["mac_products_saved"].get<uint64_t>(),
      28 * j["intersection_tests"].get<uint64_t>());
  EXPECT_LT(j["mac"]["products"].get<uint64_t>(), 28 * j["intersection_tests"].get<uint64_t>());
  EXPECT_TRUE(j["fifo"].contains("search"));
  EXPECT_GT(j["host"]["scene_bytes"].get<uint64_t>(), 0u);
  EXPECT_TRUE(j["left_out"].contains("scene_needs"));
}

// The printed summary, the stats and their flat summary show the model's figures, the same ones.
TEST(Cli, PrintedSummaryAndStatsShowTheSameFigures) {
  Tmp tmp;
  const Proc r = run_rtm(
      "render " + kScenes + "balls-1.nff --size 16x16 --pes 2 --out " + (tmp / "m.png"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = stats(tmp / "m.json");
  char line[200];
  std::snprintf(line, sizeof line, "bottleneck: %s: %s\n",
                j["bottleneck"].get<std::string>().c_str(),
                j["bottleneck_reason"].get<std::string>().c_str());
  EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
  std::snprintf(line, sizeof line,
                "cycles / MAC bound %.2f, load imbalance %.2f (longest PE working window / mean)\n",
                j["cycles_over_mac_bound"].get<double>(), j["load_imbalance"].get<double>());
  EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
  // Over the frame and over the PEs' working windows, both.
  std::snprintf(line, sizeof line,
                "utilisation over the frame: front buffer %.1f%%, search %.1f%%, MAC %.1f%%",
                100 * j["utilisation"]["front_buffer"].get<double>(),
                100 * j["utilisation"]["search"].get<double>(),
                100 * j["utilisation"]["mac"].get<double>());
  EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
  std::snprintf(
      line, sizeof line,
      "utilisation over the PEs' working windows: front buffer %.1f%%, search %.1f%%, MAC %.1f%%",
      100 * j["pe_utilisation"]["front_buffer"].get<double>(),
      100 * j["pe_utilisation"]["search"].get<double>(),
      100 * j["pe_utilisation"]["mac"].get<double>());
  EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
  std::snprintf(line, sizeof line, ", credit stall %.1f%%\n",
                100 * j["pe_utilisation"]["credit_stall"].get<double>());
  EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
  // Each PE's working window, where a waveform window counted from a PE's start begins.
  std::snprintf(line, sizeof line, "PE working windows (cycles): pe0 %llu-%llu, pe1 %llu-%llu\n",
                (unsigned long long)j["per_pe"][0]["start_cycle"].get<uint64_t>(),
                (unsigned long long)j["per_pe"][0]["cycles"].get<uint64_t>(),
                (unsigned long long)j["per_pe"][1]["start_cycle"].get<uint64_t>(),
                (unsigned long long)j["per_pe"][1]["cycles"].get<uint64_t>());
  EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
  const json& s = j["summary"];
  for (const char* k :
       {"cycles", "load_imbalance", "bottleneck", "mac_bound_cycles", "cycles_over_mac_bound"})
    EXPECT_EQ(s[k], j[k]) << k;
  EXPECT_EQ(s["mac_products"], j["mac"]["products"]);
  EXPECT_EQ(s["link_busy_cycles"], j["host"]["link_busy_cycles"]);
  for (const auto& [unit, u] : j["utilisation"].items()) EXPECT_EQ(s["util_" + unit], u) << unit;
  for (const auto& [unit, u] : j["pe_utilisation"].items())
    EXPECT_EQ(s["pe_util_" + unit], u) << unit;
  for (const auto& [phase, cycles] : j["phases"].items()) EXPECT_EQ(s[phase], cycles) << phase;
}

// Whenever the machine's counts differ from the reference's (reference.counts_match false), the
// summary says so in a line naming each count with both values, the difference and how much of it
// is in the differing pixels' trees; when they match, nothing.
TEST(Cli, TheSummarySaysHowTheCountsDifferFromTheReference) {
  Tmp tmp;
  const std::string count =
      R"( [a-z ]+ \d+ vs \d+ \([+-]\d+, [+-][0-9.e+-]+%; ([+-]\d+|all|none) in the differing pixels\))";
  const std::regex line("\nnote: counts differ from the reference \\(machine vs reference\\):" +
                        count + "(," + count + ")*; ([^\n]*)\n");
  // The wide latch: with it float32 hits flip on this frame (the default's advanced latch flips
  // none).
  const Proc differ = run_rtm(
      "render " + kScenes +
          "rings-1.nff --size 48x48 --pes 3 --partition blocks --set origin_latch=wide --out " +
          (tmp / "a.png"),
      tmp);
  ASSERT_EQ(differ.exit_code, 0) << differ.err;
  ASSERT_EQ(stats(tmp / "a.json")["reference"]["counts_match"], false);
  EXPECT_TRUE(std::regex_search(differ.out, line)) << differ.out;
  // One pixel off, and all of its shadow rays' difference in its tree.
  const Proc one = run_rtm(
      "render " + kScenes + "rings-1.nff --size 7 --preset paper --out " + (tmp / "o.png"), tmp);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(stats(tmp / "o.json")["error"]["pixels_over_1_255"], 1);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(one.out, m, line)) << one.out;
  EXPECT_TRUE(std::regex_search(
      m.str(),
      std::regex(R"(shadow rays \d+ vs \d+ \(\+\d+, [0-9.+e-]+%; all in the differing pixels\))")))
      << m.str();
  // No pixel off, yet an intersection test more: none of it can be in a differing pixel, and the
  // line says so rather than blaming a flipped hit.
  const Proc clean = run_rtm(
      "render " + kScenes + "balls-1.nff --size 9 --preset paper --out " + (tmp / "c.png"), tmp);
  ASSERT_EQ(clean.exit_code, 0) << clean.err;
  ASSERT_EQ(stats(tmp / "c.json")["error"]["pixels_over_1_255"], 0);
  ASSERT_EQ(stats(tmp / "c.json")["reference"]["counts_match"], false);
  ASSERT_TRUE(std::regex_search(clean.out, m, line)) << clean.out;
  EXPECT_EQ(m.str().find("all in the differing pixels"), std::string::npos) << m.str();
  EXPECT_NE(m.str().find("; it is all in rays of pixels within 1/255 of the reference"),
            std::string::npos)
      << m.str();
  // At fp64 the counts match: nothing.
  const Proc match = run_rtm(
      "render " + kScenes + "rings-1.nff --size 16x16 --precision fp64 --out " + (tmp / "b.png"),
      tmp);
  ASSERT_EQ(match.exit_code, 0) << match.err;
  ASSERT_EQ(stats(tmp / "b.json")["reference"]["counts_match"], true);
  EXPECT_EQ(match.out.find("counts differ"), std::string::npos) << match.out;
  EXPECT_EQ(match.out.find("warning"), std::string::npos) << match.out;
}

// `rtm config` prints a YAML file --config reads back: the same configuration, the same run.
TEST(Cli, ConfigPrintsAFileThatLoadsBack) {
  Tmp tmp;
  const Proc defaults = run_rtm("config", tmp);
  ASSERT_EQ(defaults.exit_code, 0) << defaults.err;
  EXPECT_EQ(defaults.out.rfind("# ", 0), 0u) << "a header comment first";
  EXPECT_NE(defaults.out.find("\npes: 1  "), std::string::npos) << defaults.out;
  EXPECT_NE(defaults.out.find("# processing elements (an integer in 1..16384)\n"),
            std::string::npos)
      << defaults.out;
  const std::string sets =
      " --set pes=3 --set partition=pixels --set clock_ns=2.5 --set broadcast=true";
  const Proc changed = run_rtm("config" + sets, tmp);
  ASSERT_EQ(changed.exit_code, 0) << changed.err;
  spit(tmp / "cfg.yaml", changed.out);
  const Proc again = run_rtm("config --config " + (tmp / "cfg.yaml"), tmp);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, changed.out);
  EXPECT_NE(again.out, defaults.out);
  // A render from the file is the render with the same --set options.
  const std::string scene = kScenes + "balls-1.nff --size 12x12";
  const json from_file = render(tmp, "file", scene + " --config " + (tmp / "cfg.yaml"));
  const json from_sets = render(tmp, "sets", scene + sets);
  ASSERT_FALSE(from_file.is_null() || from_sets.is_null());
  EXPECT_EQ(from_file["config"], from_sets["config"]);
  EXPECT_EQ(from_file["cycles"], from_sets["cycles"]);
  EXPECT_EQ(from_file["config"]["clock_ns"], 2.5);
}

// The stats' `config` holds each key's value as its type says (what `rtm config` writes it
// accepts): integers and numbers as JSON numbers, flags as booleans, choices as their names.
TEST(Cli, StatsConfigValuesHaveTheirKeysTypes) {
  Tmp tmp;
  const std::string sets = " --set clock_ns=2.5 --set broadcast=true --set loop_credits=3";
  const json j = render(tmp, "m", kScenes + "balls-1.nff --size 8x8" + sets);
  const Proc config = run_rtm("config" + sets, tmp);
  ASSERT_FALSE(j.is_null());
  ASSERT_EQ(config.exit_code, 0) << config.err;
  // `key: value  # meaning (what it accepts)`, the accepted values last.
  const std::regex line(
      R"(^(\w+): (\S+) +# .*\((an integer|a number|true or false|one of|a name or a path)[^()]*\)$)");
  std::istringstream lines(config.out);
  size_t keys = 0;
  for (std::string l; std::getline(lines, l);) {
    std::smatch m;
    if (!std::regex_match(l, m, line) || m[1] == "preset") continue;
    ++keys;
    const json& v = j["config"][m[1].str()];
    const std::string type = m[3], text = m[2];
    if (type == "an integer") {
      EXPECT_TRUE(v.is_number_integer()) << l;
      EXPECT_EQ(v.dump(), text) << l;
    } else if (type == "a number") {
      EXPECT_TRUE(v.is_number()) << l;
      EXPECT_EQ(v.get<double>(), std::stod(text)) << l;
    } else if (type == "true or false") {
      EXPECT_TRUE(v.is_boolean()) << l;
      EXPECT_EQ(v.dump(), text) << l;
    } else {
      EXPECT_EQ(v, text) << l;
    }
  }
  EXPECT_EQ(keys, j["config"].size()) << "every key of the stats is one of rtm config's";
  EXPECT_EQ(j["config"]["clock_ns"], 2.5);
  EXPECT_EQ(j["config"]["broadcast"], true);
  EXPECT_EQ(j["config"]["loop_credits"], 3);
  EXPECT_EQ(j["config"]["timing"], "fast");
}

// A bad configuration file is bad input (exit 2, as a bad command line), named by file and line.
TEST(Cli, ABadConfigFileExits2NamingFileAndLine) {
  Tmp tmp;
  spit(tmp / "bad.yaml", "pes: 2\nsearch_units: 300\n");
  const Proc r = run_rtm("render " + kScenes + "balls-1.nff --size 8x8 -q --config " +
                             (tmp / "bad.yaml") + " --out " + (tmp / "o.png"),
                         tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(
      r.err.find(tmp / "bad.yaml" + ":2: search_units: expected an integer in 1..256, got 300"),
      std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(tmp / "o.png"));
  spit(tmp / "typo.yaml", "pes: 2\nsearch_unit: 3\n");
  const Proc c = run_rtm("config --config " + (tmp / "typo.yaml"), tmp);
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.err.find(tmp / "typo.yaml" + ":2: search_unit: unknown machine configuration key"),
            std::string::npos)
      << c.err;
}

// docs/machine.md's generated tables are `rtm config --markdown` (the keys) and
// `rtm config --markdown --preset paper` (how paper differs); scripts/config-doc rewrites them.
TEST(Cli, TheDocsTablesAreTheGeneratedOnes) {
  Tmp tmp;
  struct Table {
    const char *doc, *marker, *args;
  };
  for (const Table& t : {Table{"machine.md", "config-keys", "config --markdown"},
                         Table{"machine.md", "preset-paper", "config --markdown --preset paper"},
                         Table{"cost.md", "tech-entries", "tech --markdown"}}) {
    const std::string doc = slurp(std::string(RTM_SOURCE_DIR) + "/docs/" + t.doc);
    const Proc r = run_rtm(t.args, tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string begin = std::string("<!-- ") + t.marker + ":begin -->\n",
                      end = std::string("<!-- ") + t.marker + ":end -->";
    const size_t from = doc.find(begin), to = doc.find(end);
    ASSERT_NE(from, std::string::npos) << t.marker;
    ASSERT_NE(to, std::string::npos) << t.marker;
    EXPECT_EQ(doc.substr(from + begin.size(), to - from - begin.size()), r.out)
        << "docs/" << t.doc << "'s " << t.marker << " table is out of date: run scripts/config-doc";
  }
}

// The paper preset renders, and the statistics say which preset a run started from.
TEST(Cli, APresetRendersAndTheStatsRecordIt) {
  Tmp tmp;
  const std::string scene = kScenes + "balls-1.nff --size 16x16";
  const json paper = render(tmp, "paper", scene + " --preset paper");
  const json plain = render(tmp, "plain", scene);
  ASSERT_FALSE(paper.is_null() || plain.is_null());
  EXPECT_EQ(paper["preset"], "paper");
  EXPECT_EQ(plain["preset"], "default");
  EXPECT_EQ(paper["config"]["mac_schedule"], "full");
  EXPECT_EQ(paper["config"]["recentre"], false);
  EXPECT_EQ(paper["mac"]["products"].get<uint64_t>(),
            28 * paper["intersection_tests"].get<uint64_t>());
  EXPECT_LE(paper["error"]["pixels_over_1_255"].get<int>(), 16 * 16 / 100);
  // The same picture: the presets differ in arithmetic and schedule, not in what is traced.
  EXPECT_EQ(paper["rays"], plain["rays"]);
}

// Preset, then configuration file, then --set: each changes what the one before left.
TEST(Cli, APresetComesBeforeTheFileAndTheFileBeforeSet) {
  Tmp tmp;
  spit(tmp / "f.yaml", "mac_schedule: sparse\nrecentre: true\npes: 2\n");
  const Proc r = run_rtm(
      "config --preset paper --config " + (tmp / "f.yaml") + " --set recentre=false --set pes=3",
      tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* line : {"\npreset: paper ", "\nmac_schedule: sparse ", "\nrecentre: false ",
                           "\npes: 3 ", "\ncoef_scaling: none "})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << " in\n" << r.out;
  // A file's preset comes before its own keys too, wherever it is written.
  spit(tmp / "g.yaml", "mac_schedule: sparse\npreset: paper\n");
  const Proc g = run_rtm("config --config " + (tmp / "g.yaml"), tmp);
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_NE(g.out.find("\nmac_schedule: sparse "), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("\ncoef_scaling: none "), std::string::npos) << g.out;
}

// `rtm config --preset paper` is a file --config reads back as the same machine, the same run.
TEST(Cli, APresetsConfigLoadsBackAsTheSameConfiguration) {
  Tmp tmp;
  const Proc paper = run_rtm("config --preset paper", tmp);
  ASSERT_EQ(paper.exit_code, 0) << paper.err;
  EXPECT_NE(paper.out.find("\npreset: paper "), std::string::npos) << paper.out;
  spit(tmp / "paper.yaml", paper.out);
  const Proc again = run_rtm("config --config " + (tmp / "paper.yaml"), tmp);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, paper.out);
  EXPECT_NE(paper.out, run_rtm("config", tmp).out);
  const std::string scene = kScenes + "balls-1.nff --size 12x12";
  const json from_file = render(tmp, "file", scene + " --config " + (tmp / "paper.yaml"));
  const json from_preset = render(tmp, "preset", scene + " --preset paper");
  ASSERT_FALSE(from_file.is_null() || from_preset.is_null());
  EXPECT_EQ(from_file["preset"], "paper");
  EXPECT_EQ(from_file["config"], from_preset["config"]);
  EXPECT_EQ(from_file["cycles"], from_preset["cycles"]);
}

// An unknown preset is a bad command line or a bad file (exit 2), named where it was written.
TEST(Cli, AnUnknownPresetExits2SayingWhichAreKnown) {
  Tmp tmp;
  const Proc r = run_rtm(
      "render " + kScenes + "balls-1.nff --size 8x8 -q --preset papr --out " + (tmp / "o.png"),
      tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("rtm: --preset: preset: expected one of default, paper, got 'papr'"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(tmp / "o.png"));
  for (const char* command : {"config --preset papr", "config --markdown --preset papr"}) {
    const Proc c = run_rtm(command, tmp);
    EXPECT_EQ(c.exit_code, 2) << command;
    EXPECT_NE(c.err.find("expected one of default, paper, got 'papr'"), std::string::npos)
        << command << ": " << c.err;
  }
  spit(tmp / "bad.yaml", "pes: 2\npreset: papr\n");
  const Proc f = run_rtm("config --config " + (tmp / "bad.yaml"), tmp);
  EXPECT_EQ(f.exit_code, 2);
  EXPECT_NE(f.err.find(tmp / "bad.yaml" + ":2: preset: expected one of default, paper, got 'papr'"),
            std::string::npos)
      << f.err;
}

// The machine against the reference, several scenes and PE counts.
struct SceneCase {
  const char* scene;
  int pes;
};
void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.scene << " on " << c.pes << " PEs"; }
class MachineVsReference : public ::testing::TestWithParam<SceneCase> {};

TEST_P(MachineVsReference, Fp64EqualsTheReference) {
  Tmp tmp;
  const SceneCase c = GetParam();
  const json j =
      render(tmp, "m",
             kScenes + c.scene + " --size 32x32 --precision fp64 --pes " + std::to_string(c.pes));
  ASSERT_FALSE(j.is_null());
  EXPECT_LE(j["error"]["max_abs"].get<double>(), 1e-6);
  EXPECT_TRUE(j["reference"]["rays_match"].get<bool>());
  // The reference crosses empty space in large steps; it must still count every voxel and test
  // the machine's one-voxel walk makes.
  EXPECT_TRUE(j["reference"]["counts_match"].get<bool>());
}

// The float32 tolerance (docs/machine.md, "Accuracy"): shading differs by float32 rounding of t
// (refined in shading), so nearly every pixel agrees to well under 1/255; a pixel can differ
// more only where a hit/miss or lit/shadowed decision sits within float32 rounding of a
// tangency, which is rare: at most 1% of pixels, and the primary hits agree on >= 99%.
TEST_P(MachineVsReference, Fp32WithinTheFloat32Tolerance) {
  Tmp tmp;
  const SceneCase c = GetParam();
  const json j =
      render(tmp, "m", kScenes + c.scene + " --size 32x32 --pes " + std::to_string(c.pes));
  ASSERT_FALSE(j.is_null());
  EXPECT_LE(j["error"]["pixels_over_1_255"].get<double>(), 0.01 * 32 * 32);
  EXPECT_LE(j["error"]["rmse"].get<double>(), 0.02);
  const json ref =
      json::parse(run_rtm("render --reference " + kScenes + c.scene + " --size 32x32 --out " +
                              (tmp / "r.exr") + " --id-map " + (tmp / "r-id.exr") + " -q",
                          tmp)
                              .exit_code == 0
                      ? slurp(tmp / "r.json")
                      : "null");
  ASSERT_FALSE(ref.is_null());
  EXPECT_GE(id_agreement(tmp / "m-id.exr", tmp / "r-id.exr"), 0.99);
}

INSTANTIATE_TEST_SUITE_P(
    Spd, MachineVsReference,
    ::testing::Values(SceneCase{"balls-1.nff", 1}, SceneCase{"balls-1.nff", 3},
                      SceneCase{"balls-1.nff", 8}, SceneCase{"rings-1.nff", 3},
                      SceneCase{"tree-2.nff", 8}, SceneCase{"mount-1.nff", 1},
                      SceneCase{"mount-1.nff", 3}, SceneCase{"lattice-1.nff", 8},
                      SceneCase{"jacks-1.nff", 3},
                      // Fine grids, where the reference skips most of the walk.
                      SceneCase{"tree-3.nff --grid 160x160x24", 2},
                      SceneCase{"balls-2.nff --grid 120x120x16", 2}),
    [](const auto& info) {
      std::string s = info.param.scene;
      s = s.substr(0, s.find('.'));
      for (char& ch : s)
        if (ch == '-') ch = '_';
      return s + "_" + std::to_string(info.param.pes) + "pe";
    });

// In double precision the hit refinement is a step of rounding size: without it the machine is
// still the reference to 1e-6, doing the same work.
TEST(Machine, Fp64WithoutTheHitRefinementStillEqualsTheReference) {
  Tmp tmp;
  for (const char* scene : {"balls-1.nff", "rings-1.nff", "shells-1.nff"}) {
    const json j =
        render(tmp, "m", kScenes + scene + " --size 32x32 --precision fp64 --set hit_refine=none");
    ASSERT_FALSE(j.is_null()) << scene;
    EXPECT_LE(j["error"]["max_abs"].get<double>(), 1e-6) << scene;
    EXPECT_EQ(j["error"]["primary_ids_differing"].get<int>(), 0) << scene;
    EXPECT_TRUE(j["reference"]["counts_match"].get<bool>()) << scene;
  }
}

TEST(Machine, ImageAndRayCountsDoNotDependOnPesOrSearchUnits) {
  Tmp tmp;
  const std::string scene = kScenes + "rings-1.nff --size 32x32";
  const json base = render(tmp, "base", scene + " --pes 1 --search-units 4");
  ASSERT_FALSE(base.is_null());
  const rtm::Image img = rtm::read_image(tmp / "base.exr");
  int n = 0;
  for (const char* args :
       {"--pes 3 --search-units 1", "--pes 8 --search-units 7 --partition blocks",
        "--pes 5 --partition strips --search-units 2",
        "--pes 6 --set gather=as_finished --set broadcast=true --set ray_generation=pe",
        "--pes 4 --set search_walk=until_occupied --set intersection_units=2"}) {
    const std::string name = "v" + std::to_string(n++);
    const json j = render(tmp, name, scene + " " + args);
    ASSERT_FALSE(j.is_null());
    EXPECT_EQ(j["rays"], base["rays"]) << args;
    EXPECT_EQ(j["voxel_steps"], base["voxel_steps"]) << args;
    EXPECT_EQ(j["intersection_tests"], base["intersection_tests"]) << args;
    EXPECT_EQ(rtm::read_image(tmp / (name + ".exr")).rgb, img.rgb) << args;
  }
}

TEST(Machine, GatheringEachPeAsItFinishesOverlapsTheGatherWithWork) {
  Tmp tmp;
  const std::string scene = kScenes + "balls-1.nff --size 48x48 --pes 8 --partition strips";
  const json after = render(tmp, "after", scene + " --set gather=after_all");
  const json as = render(tmp, "as", scene + " --set gather=as_finished");
  ASSERT_FALSE(after.is_null() || as.is_null());
  // Strips leave the PEs unbalanced, so early finishers are read while the others still work:
  // the same PE phase, a shorter tail after it.
  EXPECT_EQ(as["phases"]["pe_cycles"], after["phases"]["pe_cycles"]);
  EXPECT_LT(as["phases"]["gather_cycles"].get<double>(),
            after["phases"]["gather_cycles"].get<double>());
  EXPECT_LT(as["cycles"].get<uint64_t>(), after["cycles"].get<uint64_t>());
  EXPECT_EQ(as["cycles"].get<uint64_t>(),
            uint64_t(as["phases"]["host_preprocess_cycles"].get<double>() +
                     as["phases"]["transfer_cycles"].get<double>() +
                     as["phases"]["pe_cycles"].get<double>() +
                     as["phases"]["gather_cycles"].get<double>()));
  EXPECT_EQ(rtm::read_image(tmp / "as.exr").rgb, rtm::read_image(tmp / "after.exr").rgb);
}

TEST(Machine, ClockedAndFastMacAgreeOnAWholeFrame) {
  Tmp tmp;
  for (const char* schedule : {"full", "sparse"})
    for (const char* precision : {"fp32", "fp64"}) {
      const std::string what = std::string(schedule) + "-" + precision;
      const std::string scene = kScenes + "balls-1.nff --size 24x24 --pes 2 --precision " +
                                precision + " --mac-schedule " + schedule;
      const json fast = render(tmp, "fast" + what, scene + " --timing fast");
      const json clocked = render(tmp, "clocked" + what, scene + " --timing clocked");
      ASSERT_FALSE(fast.is_null());
      ASSERT_FALSE(clocked.is_null());
      EXPECT_EQ(fast["cycles"], clocked["cycles"]) << what;
      EXPECT_EQ(fast["mac"], clocked["mac"]) << what;
      EXPECT_EQ(fast["per_pe"], clocked["per_pe"]) << what;
      EXPECT_EQ(rtm::read_image(tmp / ("fast" + what + ".exr")).rgb,
                rtm::read_image(tmp / ("clocked" + what + ".exr")).rgb)
          << what;
    }
}

TEST(Machine, RankedArbitrationMakesClockedAndFastAgreeOnAnyFrame) {
  // rings-1 at 48x48 on 2 PEs is a frame where SystemC's own same-time order differs between
  // the timings (measured: 825,203 fast against 825,606 clocked cycles); ranked order, the
  // default, does not. Fast timing runs on the PE engine here, clocked timing on the modules.
  Tmp tmp;
  for (const char* schedule : {"sparse", "full"}) {
    const std::string scene =
        kScenes + "rings-1.nff --size 48x48 --pes 2 --mac-schedule " + schedule;
    const json fast = render(tmp, std::string("fast") + schedule, scene + " --timing fast");
    const json clocked =
        render(tmp, std::string("clocked") + schedule, scene + " --timing clocked");
    ASSERT_FALSE(fast.is_null() || clocked.is_null());
    EXPECT_EQ(fast["cycles"], clocked["cycles"]) << schedule;
    EXPECT_EQ(fast["per_pe"], clocked["per_pe"]) << schedule;
    EXPECT_EQ(fast["fifo"], clocked["fifo"]) << schedule;
    EXPECT_EQ(fast["mac"], clocked["mac"]) << schedule;
    EXPECT_EQ(rtm::read_image(tmp / (std::string("fast") + schedule + ".exr")).rgb,
              rtm::read_image(tmp / (std::string("clocked") + schedule + ".exr")).rgb);
  }
  // The order changes cycles, never the picture or the ray counts.
  const json kernel =
      render(tmp, "kernel", kScenes + "rings-1.nff --size 48x48 --pes 2 --set arbitration=kernel");
  const json ranked = render(tmp, "ranked", kScenes + "rings-1.nff --size 48x48 --pes 2");
  ASSERT_FALSE(kernel.is_null() || ranked.is_null());
  EXPECT_EQ(kernel["rays"], ranked["rays"]);
  EXPECT_EQ(rtm::read_image(tmp / "kernel.exr").rgb, rtm::read_image(tmp / "ranked.exr").rgb);
}

/// Value changes in a VCD body, and how many of them come after time `after` (in the file's unit).
std::pair<int, int> vcd_changes(const std::string& vcd, uint64_t after) {
  std::istringstream body(vcd.substr(vcd.find("$enddefinitions")));
  uint64_t now = 0;
  int changes = 0, late = 0;
  for (std::string line; std::getline(body, line);) {
    if (line.empty() || line[0] == '$') continue;
    if (line[0] == '#') {
      now = std::stoull(line.substr(1));
      continue;
    }
    ++changes;
    if (now > after) ++late;
  }
  return {changes, late};
}

TEST(Machine, VcdHoldsTheDeclaredSignalsAndTheSaveFileNamesThem) {
  Tmp tmp;
  const std::string scene =
      "render " + kScenes + "balls-1.nff --size 12x12 --timing clocked --pes 2 --vcd-pes 0,1 -q";
  const Proc r = run_rtm(scene + " --vcd " + (tmp / "w.vcd") + " --out " + (tmp / "w.png"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string vcd = slurp(tmp / "w.vcd");
  ASSERT_FALSE(vcd.empty());
  EXPECT_NE(vcd.find("$enddefinitions"), std::string::npos);
  // Every signal the GTKWave save file names must be declared in the VCD, in its scope.
  const std::string gtkw = slurp(tmp / "w.gtkw");
  ASSERT_FALSE(gtkw.empty());
  std::istringstream lines(gtkw);
  int named = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("+{", 0) != 0) continue;  // +{alias} SystemC.machine.NAME
    line = line.substr(line.find("} ") + 2);
    ASSERT_EQ(line.rfind("SystemC.machine.", 0), 0u) << line;
    ++named;
    std::string leaf = line.substr(line.rfind('.') + 1);
    leaf = leaf.substr(0, leaf.find('['));
    EXPECT_NE(vcd.find(" " + leaf + " "), std::string::npos) << line;
  }
  EXPECT_GT(named, 30);
  for (const char* s :
       {"$scope module pe0 $end", "$scope module pe1 $end", "$scope module mac $end", " m1_valid ",
        " acc ", " product_counter [31:0] ", " occupancy [31:0] ", " busy "})
    EXPECT_NE(vcd.find(s), std::string::npos) << s;
  EXPECT_GT(vcd_changes(vcd, 0).first, 1000);
  // Each MAC signal once, under one name: the unit's busy flag and ray and the clocked pipeline's
  // registers, all in the MAC's scope.
  const std::vector<std::string> names = vcd_signals(vcd);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  std::vector<std::string> busy;
  for (const std::string& n : names) {
    EXPECT_EQ(n.find("mac_unit"), std::string::npos) << n;
    if (n.rfind("SystemC.machine.pe0.intersection0.", 0) == 0 && n.size() > 5 &&
        n.compare(n.size() - 5, 5, ".busy") == 0)
      busy.push_back(n);
  }
  EXPECT_EQ(busy, (std::vector<std::string>{"SystemC.machine.pe0.intersection0.mac.busy",
                                            "SystemC.machine.pe0.intersection0.root.busy"}));
  for (const char* leaf : {"ray_id[31:0]", "adder_ray_id[31:0]", "acc", "m1_valid"})
    EXPECT_EQ(std::count(names.begin(), names.end(),
                         std::string("SystemC.machine.pe0.intersection0.mac.") + leaf),
              1)
        << leaf;

  // A window: from when the PEs got their work, 2000 cycles (20000 ns at 10 ns); nothing is
  // recorded after it (the kernel only stamps the closing time).
  const uint64_t from = stats(tmp / "w.json")["host"]["transfer_done_cycle"].get<uint64_t>();
  const Proc w =
      run_rtm(scene + " --vcd " + (tmp / "v.vcd") + " --vcd-window " + std::to_string(from) + ":" +
                  std::to_string(from + 2000) + " --out " + (tmp / "v.png"),
              tmp);
  ASSERT_EQ(w.exit_code, 0) << w.err;
  const auto [changes, late] = vcd_changes(slurp(tmp / "v.vcd"), (from + 2000) * 10);
  EXPECT_GT(changes, 100);
  EXPECT_EQ(late, 0);
}

/// The times (in the VCD's unit) of every value change after the initial values at time 0.
std::vector<uint64_t> vcd_change_times(const std::string& vcd) {
  std::istringstream body(vcd.substr(vcd.find("$enddefinitions")));
  uint64_t now = 0;
  std::vector<uint64_t> times;
  for (std::string line; std::getline(body, line);) {
    if (line.empty() || line[0] == '$') continue;
    if (line[0] == '#')
      now = std::stoull(line.substr(1));
    else if (now > 0)
      times.push_back(now);
  }
  return times;
}

TEST(Machine, AWindowCountedFromAPesStartRecordsItsFirstCycles) {
  Tmp tmp;
  const std::string scene =
      "render " + kScenes + "balls-1.nff --size 12x12 --timing clocked --pes 2 -q";
  const Proc r = run_rtm(scene + " --vcd-pes 1 --vcd-window pe1+0:300 --vcd " + (tmp / "w.vcd") +
                             " --out " + (tmp / "w.png"),
                         tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const uint64_t start = stats(tmp / "w.json")["per_pe"][1]["start_cycle"].get<uint64_t>();
  ASSERT_GT(start, 1000u);  // after the host's pre-processing
  const std::vector<uint64_t> times = vcd_change_times(slurp(tmp / "w.vcd"));
  ASSERT_GT(times.size(), 100u);
  EXPECT_GE(*std::min_element(times.begin(), times.end()), start * 10);  // 10 ns a cycle
  EXPECT_LE(*std::max_element(times.begin(), times.end()), (start + 300) * 10);
  EXPECT_NE(slurp(tmp / "w.gtkw").find("[timestart] " + std::to_string(start * 10) + "\n"),
            std::string::npos);

  // A window in the host's pre-processing records nothing, and says so once, with what would.
  const Proc early = run_rtm(
      scene + " --vcd-window 100:200 --vcd " + (tmp / "e.vcd") + " --out " + (tmp / "e.png"), tmp);
  ASSERT_EQ(early.exit_code, 0) << early.err;
  EXPECT_TRUE(vcd_change_times(slurp(tmp / "e.vcd")).empty());
  EXPECT_EQ(early.err,
            "rtm: warning: --vcd-window: cycles 100..200 hold none of the traced PEs' work (PE 0 "
            "cycles " +
                std::to_string(stats(tmp / "e.json")["per_pe"][0]["start_cycle"].get<uint64_t>()) +
                ".." +
                std::to_string(stats(tmp / "e.json")["per_pe"][0]["cycles"].get<uint64_t>()) +
                "), so the waveform recorded nothing; e.g. --vcd-window pe0+0:2000 records the "
                "first 2000 "
                "cycles of PE 0's work\n");

  // A PE without pixels never starts; a PE that does not exist is a bad command line.
  const Proc idle =
      run_rtm("render " + kScenes +
                  "balls-1.nff --size 4x4 --timing clocked --pes 2 --partition blocks -q" +
                  " --vcd-window pe1+0:100 --vcd " + (tmp / "i.vcd") + " --out " + (tmp / "i.png"),
              tmp);
  ASSERT_EQ(idle.exit_code, 0) << idle.err;
  EXPECT_NE(idle.err.find("rtm: warning: --vcd-window: PE 1 never started (it has no pixels)"),
            std::string::npos)
      << idle.err;
  const Proc none = run_rtm(scene + " --vcd-window pe2+0:100 --vcd " + (tmp / "n.vcd"), tmp);
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("names PE 2, but there are 2 PEs (pe0..pe1)"), std::string::npos)
      << none.err;
}

// Every waveform example of the README and docs/ records something: each runs as written, from
// the checkout (build/rtm the binary under test, out/ a scratch folder).
TEST(Docs, EveryWaveformExampleRecordsActivity) {
  std::vector<std::string> examples;
  std::vector<fs::path> pages{fs::path(RTM_SOURCE_DIR) / "README.md"};
  for (const auto& e : fs::directory_iterator(fs::path(RTM_SOURCE_DIR) / "docs"))
    if (e.path().extension() == ".md") pages.push_back(e.path());
  for (const fs::path& page : pages) {
    std::istringstream lines(slurp(page.string()));
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("build/rtm render", 0) == 0 && line.find(" --vcd ") != std::string::npos)
        examples.push_back(line.substr(0, line.find("  #")));
  }
  ASSERT_GE(examples.size(), 2u);
  for (std::string cmd : examples) {
    Tmp tmp;
    for (size_t at; (at = cmd.find(" out/")) != std::string::npos;)
      cmd.replace(at, 5, " " + (tmp / ""));
    cmd.replace(0, 9, RTM_BINARY);
    if (cmd.find(" --out ") == std::string::npos) cmd += " --out " + (tmp / "image.png");
    const Proc r = sh("cd " + std::string(RTM_SOURCE_DIR) + " && " + cmd + " -q", tmp);
    ASSERT_EQ(r.exit_code, 0) << cmd << "\n" << r.err;
    EXPECT_EQ(r.err.find("recorded nothing"), std::string::npos) << cmd << "\n" << r.err;
    std::string vcd = cmd.substr(cmd.find(" --vcd ") + 7);
    vcd = vcd.substr(0, vcd.find(' '));
    EXPECT_GT(vcd_change_times(slurp(vcd)).size(), 1000u) << cmd;
  }
}

/// The values `alpha` of PE 0's first MAC holds whenever it hands on a primitive's sums, from a
/// clocked VCD: α is 0 for a plane (no second-order term) and nonzero for a sphere.
std::vector<double> handed_alphas(const std::string& vcd) {
  const std::string scope = "SystemC.machine.pe0.intersection0.mac.";
  std::map<std::string, std::string> id_of;  // leaf name -> VCD id
  std::istringstream in(vcd);
  std::vector<std::string> scopes;
  std::string line;
  while (std::getline(in, line) && line.rfind("$enddefinitions", 0) != 0) {
    std::istringstream w(line);
    std::string first, kind, name, bits, id;
    w >> first;
    if (first == "$scope") {
      w >> kind >> name;
      scopes.push_back(name);
    } else if (first == "$upscope") {
      scopes.pop_back();
    } else if (first == "$var") {
      w >> kind >> bits >> id >> name;
      std::string full;
      for (const std::string& s : scopes) full += s + ".";
      if (full == scope) id_of[name] = id;
    }
  }
  const std::string alpha = id_of["alpha"], valid = id_of["sums_valid"];
  EXPECT_FALSE(alpha.empty() || valid.empty()) << "no MAC pipeline in the waveform";
  std::vector<double> handed;
  double now = 0;
  bool valid_now = false;  // sums_valid rose in this time step, in which alpha may change after it
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (valid_now) handed.push_back(now);
      valid_now = false;
    }
    if (line[0] == 'r' && line.substr(line.find(' ') + 1) == alpha) now = std::stod(line.substr(1));
    if (line == "1" + valid) valid_now = true;
  }
  if (valid_now) handed.push_back(now);
  return handed;
}

// The README's waveform example shows the MAC testing a sphere in its window, not only the floor.
TEST(Docs, TheReadmesWaveformExampleShowsASphereTest) {
  std::string cmd;
  std::istringstream lines(slurp(std::string(RTM_SOURCE_DIR) + "/README.md"));
  for (std::string line; cmd.empty() && std::getline(lines, line);)
    if (line.rfind("build/rtm render", 0) == 0 && line.find(" --vcd ") != std::string::npos)
      cmd = line.substr(0, line.find("  #"));
  ASSERT_FALSE(cmd.empty());
  ASSERT_NE(cmd.find("--timing clocked"), std::string::npos) << cmd;
  Tmp tmp;
  for (size_t at; (at = cmd.find(" out/")) != std::string::npos;)
    cmd.replace(at, 5, " " + (tmp / ""));
  cmd.replace(0, 9, RTM_BINARY);
  const Proc r = sh(
      "cd " + std::string(RTM_SOURCE_DIR) + " && " + cmd + " --out " + (tmp / "image.png") + " -q",
      tmp);
  ASSERT_EQ(r.exit_code, 0) << cmd << "\n" << r.err;
  std::string vcd = cmd.substr(cmd.find(" --vcd ") + 7);
  const std::vector<double> alphas = handed_alphas(slurp(vcd.substr(0, vcd.find(' '))));
  EXPECT_GT(std::count(alphas.begin(), alphas.end(), 0.0), 0) << "a floor test";
  EXPECT_GT(std::count_if(alphas.begin(), alphas.end(), [](double a) { return a != 0; }), 0)
      << "a sphere test";
}

// scripts/run passes its arguments to rtm render, an --out or --stats included (it used to pass
// its own --out too, and CLI11 refused two). Run from a copy whose setup does nothing.
TEST(Cli, ScriptsRunLetsTheUserNameTheOutputs) {
  Tmp tmp;
  fs::create_directories(tmp / "scripts");
  fs::copy_file(fs::path(RTM_SOURCE_DIR) / "scripts/run", tmp / "scripts/run");
  spit(tmp / "scripts/setup", "#!/bin/sh\n");
  fs::permissions(tmp / "scripts/setup", fs::perms::owner_all);
  const std::string run =
      "RTM_BUILD_DIR=" + fs::path(RTM_BINARY).parent_path().string() + " " + (tmp / "scripts/run");
  const Proc mine = sh(run + " --size 8x8 -q --out " + (tmp / "mine.png"), tmp);
  EXPECT_EQ(mine.exit_code, 0) << mine.err;
  EXPECT_TRUE(fs::exists(tmp / "mine.png"));
  EXPECT_TRUE(fs::exists(tmp / "mine.json"));
  const Proc plain = sh(run + " --size 8x8 -q", tmp);
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_TRUE(fs::exists(tmp / "out/default.png"));
  EXPECT_TRUE(fs::exists(tmp / "out/default.json"));
}

TEST(Cli, WarnsOfIdlePesAndOfAFastWaveformWithoutTheMac) {
  Tmp tmp;
  const Proc idle =
      run_rtm("render --pes 3 --partition blocks --size 10x10 -q --out " + (tmp / "i.png"), tmp);
  EXPECT_EQ(idle.exit_code, 0) << idle.err;
  EXPECT_EQ(idle.err,
            "rtm: warning: 2 of 3 PEs have no pixels to render (partition blocks, tile 16, 10x10 "
            "pixels): "
            "they stay idle\n");
  const Proc fast = run_rtm("render " + kScenes + "balls-1.nff --size 8x8 -q --vcd " +
                                (tmp / "f.vcd") + " --out " + (tmp / "f.png"),
                            tmp);
  EXPECT_EQ(fast.exit_code, 0) << fast.err;
  EXPECT_NE(fast.err.find("rtm: warning: --vcd in fast timing"), std::string::npos) << fast.err;
  EXPECT_NE(fast.err.find("need --timing clocked"), std::string::npos) << fast.err;
  EXPECT_EQ(std::count(fast.err.begin(), fast.err.end(), '\n'), 1) << fast.err;
}

// --vcd creates its folder as --out does; where it cannot write, one line says why before any
// simulation, a bad command line like every unwritable output.
// Each PE's local memory holds the scene copy, its primary rays and its frame buffer; what is
// left is the spill area. A PE they do not fit in is refused before the simulation, by name.
TEST(Cli, LocalMemoryIsLaidOutReportedAndTooSmallAMemoryIsRefused) {
  Tmp tmp;
  const std::string scene =
      "render " + kScenes + "balls-1.nff --size 16x16 --pes 2 --out " + (tmp / "o.png");
  const Proc ok = run_rtm(scene + " --set local_memory_bytes=1000000", tmp);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("local memory: pe0 uses"), std::string::npos) << ok.out;
  const json j = stats(tmp / "o.json");
  const json& m = j["memory"];
  EXPECT_EQ(m["capacity_bytes"].get<uint64_t>(), 1000000u);
  uint64_t used = 0;
  for (const auto& [name, bytes] : m["sections_bytes"].items()) used += bytes.get<uint64_t>();
  EXPECT_EQ(m["used_bytes"].get<uint64_t>(), used);
  const uint64_t scene_copy = m["sections_bytes"]["primitives"].get<uint64_t>() +
                              m["sections_bytes"]["voxel data"].get<uint64_t>() +
                              m["sections_bytes"]["lights and materials"].get<uint64_t>();
  EXPECT_EQ(scene_copy, j["host"]["scene_bytes"].get<uint64_t>());
  EXPECT_EQ(m["sections_bytes"]["frame buffer"].get<uint64_t>(),
            128u * 16);  // 16x16 over 2 PEs, 16 bytes a pixel
  EXPECT_EQ(m["spill_area_bytes"].get<uint64_t>(), 1000000u - used);
  EXPECT_EQ(m["spill_area_rays"].get<uint64_t>(),
            (1000000u - used) / m["spill_record_bytes"].get<uint64_t>());
  EXPECT_EQ(j["per_pe"][1]["memory_used_bytes"].get<uint64_t>(), used);

  const Proc small = run_rtm(scene + " --set local_memory_bytes=" + std::to_string(used - 1), tmp);
  EXPECT_EQ(small.exit_code, 1);
  EXPECT_EQ(small.err.rfind("rtm: local memory too small: PE 0 needs " + std::to_string(used) +
                                " bytes (primitives ",
                            0),
            0u)
      << small.err;
  EXPECT_NE(
      small.err.find("frame buffer 2048 B) but local_memory_bytes is " + std::to_string(used - 1)),
      std::string::npos)
      << small.err;
  EXPECT_EQ(std::count(small.err.begin(), small.err.end(), '\n'), 1) << small.err;
  EXPECT_FALSE(fs::exists(tmp / "o.png"));
}

TEST(Cli, AWaveformFolderIsCreatedOrItsFailureIsOneLine) {
  Tmp tmp;
  const std::string scene = "render " + kScenes + "balls-1.nff --size 8x8 --timing clocked -q";
  const Proc made =
      run_rtm(scene + " --vcd " + (tmp / "new/deeper/w.vcd") + " --out " + (tmp / "o.png"), tmp);
  EXPECT_EQ(made.exit_code, 0) << made.err;
  EXPECT_TRUE(fs::exists(tmp / "new/deeper/w.vcd"));
  EXPECT_TRUE(fs::exists(tmp / "new/deeper/w.gtkw"));
  spit(tmp / "file", "");
  const Proc r =
      run_rtm(scene + " --vcd " + (tmp / "file/w.vcd") + " --out " + (tmp / "p.png"), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "rtm: --vcd: " + (tmp / "file/w.vcd") + ": cannot write: Not a directory\n");
  EXPECT_FALSE(fs::exists(tmp / "p.png"));
  for (const char* option : {"--out", "--stats", "--id-map", "--event-log"}) {
    const Proc o = run_rtm(scene + " " + option + " " + (tmp / "file/x.exr"), tmp);
    EXPECT_EQ(o.exit_code, 2) << option << ": " << o.err;
    EXPECT_EQ(o.err, "rtm: " + std::string(option) + ": " + (tmp / "file/x.exr") +
                         ": cannot write: Not a directory\n");
  }
  fs::create_directory(tmp / "dir.png");
  const Proc folder = run_rtm(scene + " --out " + (tmp / "dir.png"), tmp);
  EXPECT_EQ(folder.exit_code, 2) << folder.err;
  EXPECT_NE(folder.err.find("cannot write: Is a directory"), std::string::npos) << folder.err;
}

// A bounded spill area on random small machines: each frame either renders exactly the image and
// rays of the unbounded machine (only timing moves: new primary rays wait for room) or, when a ray
// tree outgrows the memory, stops with the one error that says so; never a deadlock or a lost ray.
TEST(Machine, ABoundedSpillAreaNeverDeadlocksAndLosesNoRay) {
  Tmp tmp;
  std::mt19937 rng(2027);
  const char* scenes[] = {"balls-1.nff", "tree-2.nff"};
  int throttled = 0;
  for (int i = 0; i < 6; ++i) {
    const std::string args =
        kScenes + scenes[i % 2] + random_small_machine(rng, 4) + " --set loop_credits=0";
    const json free = render(tmp, "free" + std::to_string(i), args);
    ASSERT_FALSE(free.is_null()) << args;
    const uint64_t used = free["memory"]["used_bytes"].get<uint64_t>();
    const uint64_t spill = rng() % 24, on_chip = 1 + rng() % 4;
    const std::string bounded =
        args + " --set local_memory_bytes=" +
        std::to_string(used + spill * free["memory"]["spill_record_bytes"].get<uint64_t>()) +
        " --set front_buffer_capacity=" + std::to_string(on_chip);
    const std::string name = "bounded" + std::to_string(i);
    const Proc r = run_rtm("render " + bounded + " --out " + (tmp / (name + ".exr")) + " --stats " +
                               (tmp / (name + ".json")) + " -q",
                           tmp);
    if (r.exit_code == 1) {
      EXPECT_EQ(r.err.rfind("rtm: local memory too small for the ray trees: PE ", 0), 0u)
          << bounded << "\n"
          << r.err;
      continue;
    }
    ASSERT_EQ(r.exit_code, 0) << bounded << "\n" << r.err;
    const json j = json::parse(slurp(tmp / (name + ".json")));
    EXPECT_EQ(j["rays"], free["rays"]) << bounded;
    EXPECT_EQ(rtm::read_image(tmp / (name + ".exr")).rgb,
              rtm::read_image(tmp / ("free" + std::to_string(i) + ".exr")).rgb)
        << bounded;
    throttled += j["cycles"] != free["cycles"];
  }
  EXPECT_GT(throttled, 0) << "no bounded frame took a different time: the bound was never felt";
}

TEST(Machine, RandomSmallConfigurationsNeverDeadlock) {
  Tmp tmp;
  std::mt19937 rng(2026);
  const char* scenes[] = {"balls-1.nff", "mount-1.nff", "tree-2.nff"};
  for (int i = 0; i < 10; ++i) {
    std::ostringstream args;
    args << kScenes << scenes[i % 3] << random_small_machine(rng, 5) << " --partition "
         << (i % 2   ? "blocks"
             : i % 4 ? "dynamic --set tile=5"
                     : "scanlines")
         << " --set arbitration=" << (i % 3 ? "kernel" : "ranked");
    const json j = render(tmp, "r" + std::to_string(i), args.str());
    ASSERT_FALSE(j.is_null()) << args.str();
    EXPECT_TRUE(j["reference"]["rays_match"].get<bool>() ||
                j["error"]["pixels_over_1_255"].get<int>() <= 3)
        << args.str();
  }
}

TEST(Machine, TheUnregulatedLoopDeadlocksAndIsReported) {
  Tmp tmp;
  const std::string tiny_fifos =
      " --set flow_control=none --set search_fifo_depth=1 --set intersect_fifo_depth=1 --set "
      "feedback_fifo_depth=1"
      " --set shade_fifo_depth=1 --set root_fifo_depth=1";
  const Proc r = run_rtm("render " + kScenes + "balls-1.nff --size 24x24" + tiny_fifos + " --out " +
                             (tmp / "x.png") + " -q",
                         tmp);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("deadlock"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("search_fifo 1/1"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(tmp / "x.png"));
  // The clocked model, whose clock would otherwise run forever, is stopped and reported too.
  const Proc c = run_rtm("render " + kScenes + "balls-1.nff --size 24x24 --timing clocked" +
                             tiny_fifos + " --out " + (tmp / "y.png") + " -q",
                         tmp);
  EXPECT_EQ(c.exit_code, 3);
  EXPECT_FALSE(fs::exists(tmp / "y.png"));
  // With SystemC's own same-time order, where a unit facing a full FIFO waits for its read event.
  const Proc k = run_rtm("render " + kScenes + "balls-1.nff --size 24x24 --set arbitration=kernel" +
                             tiny_fifos + " --out " + (tmp / "z.png") + " -q",
                         tmp);
  EXPECT_EQ(k.exit_code, 3) << k.err;
  EXPECT_FALSE(fs::exists(tmp / "z.png"));
}

// The image library is found before any work is done, so a missing one costs no render.
TEST(Cli, MissingImageLibraryIsReportedBeforeRendering) {
  Tmp tmp;
  const std::string args =
      " render " + kScenes + "balls-1.nff --size 8x8 -q --out " + (tmp / "o.png");
  const Proc missing =
      sh("RTM_IMAGE_LIBRARY=/nonexistent/librtm_image.so " + std::string(RTM_BINARY) + args, tmp);
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("/nonexistent/librtm_image.so"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(tmp / "o.png"));
  EXPECT_FALSE(fs::exists(tmp / "o.json"));
  const std::string beside = (fs::path(RTM_BINARY).parent_path() / "librtm_image.so").string();
  const Proc named = sh("RTM_IMAGE_LIBRARY=" + beside + " " + std::string(RTM_BINARY) + args, tmp);
  EXPECT_EQ(named.exit_code, 0) << named.err;
  EXPECT_TRUE(fs::exists(tmp / "o.png"));
}

// Bad input: a clear message, a non-zero exit, no output file.
struct BadCase {
  const char* name;
  const char* file_text;  ///< written to bad.nff / bad.yaml when not null
  const char* ext;
  const char* args;
  const char* message;
};
void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }
class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, ClearMessageNonZeroExitNoOutput) {
  Tmp tmp;
  const BadCase c = GetParam();
  std::string scene;
  if (c.file_text) {
    scene = tmp / (std::string("bad.") + c.ext);
    std::ofstream(scene) << c.file_text;
  }
  const Proc r =
      run_rtm("render " + scene + " " + c.args + " --out " + (tmp / "o.png") + " -q", tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(tmp / "o.png"));
  EXPECT_FALSE(fs::exists(tmp / "o.json"));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadInput,
    ::testing::Values(
        BadCase{"MalformedNff",
                "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\nf 1 0 0 1 "
                "0 1 0 1\ns 0 0 zero 1\n",
                "nff", "", "bad.nff:9:"},
        BadCase{"NanCoefficient",
                "camera: {eye: [0, 0, 5], look_at: [0, 0, 0]}\nmaterials: {m: {}}\nprimitives:\n"
                "  - {quadric: {coefficients: [1, 1, 1, 0, 0, 0, 0, 0, 0, .nan], box: {min: [-1, "
                "-1, -1], max: [1, 1, 1]}}, material: m}\n",
                "yaml", "", "bad.yaml:4:"},
        BadCase{"MissingFile", nullptr, "", "/nonexistent/scene.nff", "/nonexistent/scene.nff"},
        BadCase{"ZeroAreaImage", nullptr, "", "--size 0x10", "--size"},
        BadCase{"UnknownConfigKey", nullptr, "", "--set warp_drive=1", "warp_drive"},
        BadCase{"ImpossibleCredits", nullptr, "", "--set loop_credits=99", "loop_credits"},
        BadCase{"BadTiming", nullptr, "", "--timing slow", "timing"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
