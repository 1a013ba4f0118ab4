// The command line and the summary, consistent: a bad option value is a usage error (exit 2, one
// line naming the option), --help gives the ranges the checks enforce, --size N is NxN, the
// summary names the machine that ran, and every build names its commit.
#include <cmath>
#include <limits>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "scene/scene_checks.h"

using nlohmann::json;
using namespace rtm::test;

namespace {

const std::string kSource = std::string(RTM_SOURCE_DIR) + "/";
const std::string kScenes = kSource + "scenes/spd/";

struct BadValue {
  const char* name;
  const char* args;    ///< after `rtm`
  const char* option;  ///< the message names it
};
void PrintTo(const BadValue& c, std::ostream* os) { *os << c.name; }
class BadOptionValue : public testing::TestWithParam<BadValue> {};

TEST_P(BadOptionValue, Exits2WithOneLineNamingTheOption) {
  Tmp tmp;
  const BadValue& c = GetParam();
  const std::string args = c.args;
  const bool render = args.rfind("render", 0) == 0;
  const Proc r =
      run_rtm(args + (args.find("--out") == std::string::npos ? " --out " + (tmp / "o.png") : "") +
                  (render ? " -q" : ""),
              tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("rtm: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(c.option), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(tmp / "o.png"));
}

// `--out` is added to each that has none.
INSTANTIATE_TEST_SUITE_P(
    Cases, BadOptionValue,
    testing::Values(
        BadValue{"JpegImage", "render --size 4 --out t.jpg", "--out"},
        BadValue{"PngIdMap", "render --size 4 --id-map t.png", "--id-map"},
        BadValue{"PngErrorMap", "render --size 4 --error-map t.png", "--error-map"},
        BadValue{"ThresholdOne", "render --size 4 --threshold 1", "--threshold"},
        BadValue{"ThresholdNan", "render --size 4 --threshold nan", "--threshold"},
        BadValue{"ThresholdText", "render --size 4 --threshold high", "--threshold"},
        BadValue{"NegativeSpawnOffset", "render --size 4 --spawn-offset -1", "--spawn-offset"},
        BadValue{"InfiniteSpawnOffset", "render --size 4 --spawn-offset inf", "--spawn-offset"},
        BadValue{"DepthZero", "render --size 4 --max-depth 0", "--max-depth"},
        BadValue{"SizeZero", "render --size 0", "--size"},
        BadValue{"SizeTooLarge", "render --size 20000", "--size"},
        BadValue{"SizeText", "render --size big", "--size"},
        BadValue{"GridZero", "render --size 4 --grid 0", "--grid"},
        BadValue{"PesZero", "render --size 4 --pes 0", "--pes"},
        BadValue{"SlowTiming", "render --size 4 --timing slow", "--timing"},
        BadValue{"Fp16", "render --size 4 --precision fp16", "--precision"},
        BadValue{"RoundPartition", "render --size 4 --partition rounds", "--partition"},
        BadValue{"SearchUnitsZero", "render --size 4 --search-units 0", "--search-units"},
        BadValue{"HalfSchedule", "render --size 4 --mac-schedule half", "--mac-schedule"},
        BadValue{"SpawnPolicy", "render --size 4 --spawn-policy far", "--spawn-policy"},
        BadValue{"MemoryText", "render --size 4 --max-memory lots", "--max-memory"},
        BadValue{"RaysZero", "render --size 4 --max-rays 0", "--max-rays"},
        BadValue{"ThreadsNegative", "render --size 4 --threads -1", "--threads"},
        BadValue{"VcdWindow", "render --size 4 --vcd-window soon", "--vcd-window"},
        BadValue{"VcdPes", "render --size 4 --vcd-pes 3", "--vcd-pes"},
        BadValue{"UnknownPreset", "render --size 4 --preset fastest", "--preset"},
        BadValue{"UnknownKey", "render --size 4 --set warp=1", "--set"},
        BadValue{"PovSize", "pov --size 0x4", "--size"},
        BadValue{"PovUnwritable", "pov --out /proc/none/x.pov", "--out"}),
    [](const auto& info) { return std::string(info.param.name); });

/// The line of `rtm render --help` that describes `option`.
std::string help_line(const std::string& help, const std::string& option) {
  std::istringstream lines(help);
  for (std::string line; std::getline(lines, line);)
    if (line.find("  " + option + " ") != std::string::npos) return line;
  ADD_FAILURE() << option << " is not in the help:\n" << help;
  return "";
}

std::string number_text(double x) {
  std::ostringstream s;
  s.precision(std::numeric_limits<double>::max_digits10);
  s << x;
  return s.str();
}

// Each scene setting's range is declared once (scene/scene_checks.h): --help shows it, values at
// its ends are taken or refused as it says, and a value outside it is a bad command line.
TEST(CommandLine, TheRangesInTheHelpAreTheRangesEnforced) {
  Tmp tmp;
  const Proc help = run_rtm("render --help", tmp);
  ASSERT_EQ(help.exit_code, 0) << help.err;
  const std::string render = "render --reference --size 2 -q --out " + (tmp / "o.png") + " ";
  for (auto [option, range] : {std::pair{"--threshold", rtm::scene_checks::kThresholdRange},
                               {"--spawn-offset", rtm::scene_checks::kSpawnOffsetRange}}) {
    EXPECT_NE(help_line(help.out, option).find(range.text()), std::string::npos)
        << option << ": " << range.text();
    const std::string lo = number_text(range.lo), below = number_text(range.lo - 0.5);
    EXPECT_EQ(run_rtm(render + option + " " + lo, tmp).exit_code, 0) << option << " " << lo;
    EXPECT_EQ(run_rtm(render + option + " " + below, tmp).exit_code, 2) << option << " " << below;
    const std::string hi = number_text(range.hi);
    EXPECT_EQ(run_rtm(render + option + " " + hi, tmp).exit_code, range.hi_open ? 2 : 0)
        << option << " " << hi;
    if (std::isfinite(range.hi)) {
      const std::string inside = number_text(std::nextafter(range.hi, range.lo));
      EXPECT_EQ(run_rtm(render + option + " " + inside, tmp).exit_code, 0)
          << option << " " << inside;
    }
  }
}

// --size N is NxN, as a sweep's sizes are, for `rtm render` and `rtm pov`.
TEST(CommandLine, ASizeOfOneNumberIsASquare) {
  Tmp tmp;
  const json j = render(tmp, "s", "--reference --size 7");
  ASSERT_FALSE(j.is_null());
  EXPECT_EQ(j["width"], 7);
  EXPECT_EQ(j["height"], 7);
  const Proc pov = run_rtm("pov --size 7 --out " + (tmp / "s.pov"), tmp);
  ASSERT_EQ(pov.exit_code, 0) << pov.err;
  EXPECT_EQ(pov.out, "pov: " + (tmp / "s.pov") + " (" + std::to_string(j["primitives"].get<int>()) +
                         " primitives, 7x7)\n");
  EXPECT_TRUE(std::filesystem::exists(tmp / "s.pov"));
}

/// The summary's first line.
std::string first_line(const std::string& out) { return out.substr(0, out.find('\n')); }

// The summary's first line names the preset and each key on which the run's machine differs from
// it, whether set by a flag, --set or a file.
TEST(CommandLine, TheSummaryNamesThePresetAndEveryKeyApartFromIt) {
  Tmp tmp;
  const std::string scene = "render " + kScenes + "balls-1.nff --size 8 --out " + (tmp / "o.png");
  const Proc plain = run_rtm(scene, tmp);
  const Proc paper = run_rtm(scene + " --preset paper", tmp);
  const Proc set = run_rtm(scene + " --set origin_latch=wide --pes 2", tmp);
  const Proc paper_set = run_rtm(scene + " --preset paper --set mac_schedule=sparse", tmp);
  for (const Proc* p : {&plain, &paper, &set, &paper_set}) ASSERT_EQ(p->exit_code, 0) << p->err;
  EXPECT_TRUE(
      std::regex_match(first_line(plain.out), std::regex(R"(balls-1: 8x8, .*; preset default)")))
      << plain.out;
  EXPECT_TRUE(
      std::regex_match(first_line(paper.out), std::regex(R"(balls-1: 8x8, .*; preset paper)")))
      << paper.out;
  EXPECT_TRUE(std::regex_search(first_line(set.out),
                                std::regex(R"(; preset default, then pes=2, origin_latch=wide$)")))
      << set.out;
  EXPECT_TRUE(std::regex_search(first_line(paper_set.out),
                                std::regex(R"(; preset paper, then mac_schedule=sparse$)")))
      << paper_set.out;
}

// Every count the summary prints has its unit, and a count of one is singular.
TEST(CommandLine, TheSummarysCountsHaveUnitsAndTheirPluralsAreRight) {
  Tmp tmp;
  // rings-1 at 7x7 in the paper's arithmetic has exactly one pixel off (checked from the stats).
  const Proc r = run_rtm(
      "render " + kScenes + "rings-1.nff --size 7 --preset paper --out " + (tmp / "o.png"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(tmp / "o.json"));
  const uint64_t off = j["error"]["pixels_over_1_255"], hits = j["error"]["primary_ids_differing"];
  EXPECT_NE(r.out.find(", " + std::to_string(off) + (off == 1 ? " pixel off" : " pixels off")),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(std::to_string(hits) +
                       (hits == 1 ? " primary hit differs" : " primary hits differ")),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find(" 1 pixels"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("why they differ (first ray to part from the reference): 1 pixel "),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(std::regex_search(
      r.out,
      std::regex(
          R"(contention stalls \d+ requester-cycles, results waiting \d+ requester-cycles)")))
      << r.out;
  EXPECT_EQ(off, 1u) << "the frame no longer has the one pixel off this test is for";
}

// `rtm --version` names the version, the commit and whether the tree was modified; every stats
// file records the same.
TEST(CommandLine, TheVersionNamesTheBuildsCommitAndTheStatsRecordIt) {
  Tmp tmp;
  const Proc v = run_rtm("--version", tmp);
  ASSERT_EQ(v.exit_code, 0) << v.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_match(
      v.out, m,
      std::regex(R"(rtm (\S+) \(commit ([0-9a-f]{40}|unknown)(, modified|, unmodified)?\)\n)")))
      << v.out;
  const json j = render(tmp, "s", "--reference --size 2");
  ASSERT_FALSE(j.is_null());
  EXPECT_EQ(j["build"]["version"], m[1].str());
  EXPECT_EQ(j["build"]["commit"], m[2].str());
  EXPECT_EQ(j["build"]["modified"],
            m[3].matched ? json(m[3].str() == ", modified") : json(nullptr));
  // Built from this checkout: the commit is one of its own.
  if (m[2] != "unknown") {
    EXPECT_EQ(sh("git -C " + kSource + " cat-file -e " + m[2].str() + "^{commit}", tmp).exit_code,
              0)
        << m[2];
  }
}

/// Runs cmake/build_info.cmake on the sources in `dir`, returns the file it writes.
std::string build_info_for(const std::string& dir, const Tmp& tmp) {
  const Proc r =
      sh(std::string(RTM_CMAKE) + " -DSOURCE_DIR=" + dir + " -DVERSION=9.9 -DTEMPLATE=" + kSource +
             "cmake/build_info.cpp.in -DOUT=" + (tmp / "info.cpp") + " -P " + kSource +
             "cmake/build_info.cmake",
         tmp);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  return slurp(tmp / "info.cpp");
}

// The build's commit is read from git when rtm is built: from a checkout, its commit and whether a
// tracked file differs; from sources without one (a tarball), unknown.
TEST(CommandLine, TheBuildReadsItsCommitFromGitOrSaysUnknown) {
  Tmp tmp;
  const std::string src = tmp / "src";
  std::filesystem::create_directories(src);
  spit(src + "/a.txt", "one\n");
  EXPECT_NE(build_info_for(src, tmp).find(R"({"9.9", "unknown", std::nullopt})"), std::string::npos)
      << slurp(tmp / "info.cpp");
  const std::string git = "git -C " + src + " -c user.name=t -c user.email=t@t ";
  ASSERT_EQ(
      sh(git + "init -q && " + git + "add a.txt && " + git + "commit -q -m one", tmp).exit_code, 0);
  const std::string head = sh(git + "rev-parse HEAD", tmp).out.substr(0, 40);
  EXPECT_NE(build_info_for(src, tmp).find("{\"9.9\", \"" + head + "\", false}"), std::string::npos)
      << slurp(tmp / "info.cpp");
  spit(src + "/a.txt", "two\n");
  EXPECT_NE(build_info_for(src, tmp).find("{\"9.9\", \"" + head + "\", true}"), std::string::npos)
      << slurp(tmp / "info.cpp");
  spit(src + "/a.txt", "one\n");
  spit(src + "/untracked.txt", "x\n");  // a build folder, an output: not the sources
  EXPECT_NE(build_info_for(src, tmp).find("{\"9.9\", \"" + head + "\", false}"), std::string::npos)
      << slurp(tmp / "info.cpp");
}

}  // namespace
