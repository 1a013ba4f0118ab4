// The statistics' contract: real renders of every kind validate against docs/stats.schema.json
// (through scripts/check-stats), and the head of a stats file names the run and the exact scene it
// read. That the schema names what the unit table declares is
// model/frame/stats_schema_test.cpp's.
#include <cstdio>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "fnv1a.h"

using nlohmann::json;
using namespace rtm::test;

namespace {

const std::string kSource = std::string(RTM_SOURCE_DIR) + "/";
const std::string kSchema = kSource + "docs/stats.schema.json";
const std::string kScenes = kSource + "scenes/spd/";

struct Case {
  const char* name;
  std::string args;  ///< `rtm render` arguments
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class StatsSchema : public testing::TestWithParam<Case> {};

// Each kind of stats file: both timings (the engine and the modules), the reference renderer's, PEs
// without pixels, the reference's counts matched (fp64) or not (fp32), skipped scene records, the
// built-in scene, a preset.
const Case kCases[] = {
    {"FastTwoPes", kScenes + "balls-1.nff --size 16x16 --pes 2"},
    {"ClockedTwoPes", kScenes + "balls-1.nff --size 12x12 --pes 2 --timing clocked"},
    {"Reference", kScenes + "balls-1.nff --size 16x16 --reference"},
    {"PesWithoutPixels", kScenes + "balls-1.nff --size 10x10 --pes 3 --partition blocks"},
    {"Fp64CountsMatch", kScenes + "rings-1.nff --size 16x16 --precision fp64"},
    {"Fp32CountsDiffer", kScenes + "rings-1.nff --size 48x48 --pes 3 --partition blocks"},
    {"SkippedRecords", kSource + "scenes/spd-corpus/teapot-1.nff --size 12x12"},
    {"DefaultScene", "--size 16x12 --search-units 2"},
    {"PaperPreset", kScenes + "rings-1.nff --size 12x12 --preset paper"},
};

TEST_P(StatsSchema, ARealRenderValidates) {
  Tmp tmp;
  const json j = render(tmp, "s", GetParam().args);
  ASSERT_FALSE(j.is_null());
  const Proc check =
      sh("/usr/bin/python3 " + kSource + "scripts/check-stats " + (tmp / "s.json"), tmp);
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_EQ(check.out, (tmp / "s.json") + ": ok (schema_version " +
                           std::to_string(j["schema_version"].get<int>()) + ")\n");
}

INSTANTIATE_TEST_SUITE_P(Renders, StatsSchema, testing::ValuesIn(kCases),
                         [](const testing::TestParamInfo<Case>& i) {
                           return std::string(i.param.name);
                         });

// The cases above reach what they are meant to.
TEST(StatsContract, CoverWhatTheyAreNamedFor) {
  Tmp tmp;
  const json idle =
      render(tmp, "idle", kScenes + "balls-1.nff --size 10x10 --pes 3 --partition blocks");
  const json fp64 = render(tmp, "fp64", kScenes + "rings-1.nff --size 16x16 --precision fp64");
  const json fp32 =
      render(tmp, "fp32", kScenes + "rings-1.nff --size 48x48 --pes 3 --partition blocks");
  ASSERT_FALSE(idle.is_null() || fp64.is_null() || fp32.is_null());
  EXPECT_EQ(idle["per_pe"][2]["rays"], 0) << "a PE without pixels";
  EXPECT_EQ(fp64["reference"]["counts_match"], true);
  EXPECT_EQ(fp32["reference"]["counts_match"], false);
}

// A schema that rejects nothing would pass every render: a few broken files must fail.
TEST(StatsContract, BrokenStatsAreRejected) {
  Tmp tmp;
  const json good = render(tmp, "good", kScenes + "balls-1.nff --size 8x8");
  ASSERT_FALSE(good.is_null());
  auto rejected = [&](json j, const std::string& what) {
    spit(tmp / "bad.json", j.dump());
    const Proc check =
        sh("/usr/bin/python3 " + kSource + "scripts/check-stats " + (tmp / "bad.json"), tmp);
    EXPECT_EQ(check.exit_code, 1) << what << "\n" << check.out << check.err;
  };
  json j = good;
  j["unknown_key"] = 1;
  rejected(j, "a key the schema does not know");
  j = good;
  j.erase("bottleneck_reason");
  rejected(j, "a required key missing");
  j = good;
  j["bottleneck"] = "disk";
  rejected(j, "a bottleneck the model does not name");
  j = good;
  j["pe_issue"]["mac"] = 1.5;
  rejected(j, "a share above 1");
  j = good;
  j["per_pe"][0]["search_units"][0].erase("issue");
  rejected(j, "a search unit without its issue share");
  j = good;
  j["config"]["pes"] = json::array({1});
  rejected(j, "a config value that is no number, flag or name");
  j = good;
  j["schema_version"] = good["schema_version"].get<int>() + 1;
  rejected(j, "another format version");
  j = good;
  j["build"]["commit"] = "HEAD";
  rejected(j, "a commit that is no hash");
  j = good;
  j.erase("build");
  rejected(j, "no build");
  spit(tmp / "bad.json", "{\"schema_version\": ");
  const Proc truncated =
      sh("/usr/bin/python3 " + kSource + "scripts/check-stats " + (tmp / "bad.json"), tmp);
  EXPECT_EQ(truncated.exit_code, 1) << truncated.out << truncated.err;
  EXPECT_EQ(truncated.err, "") << "a message, not a traceback";
  EXPECT_NE(truncated.out.find(tmp / "bad.json"), std::string::npos) << truncated.out;
}

// The head names the run: the command line as given, the scene file and a hash of its bytes.
TEST(StatsContract, TheHeadNamesTheRunAndTheScene) {
  Tmp tmp;
  const std::string scene = kScenes + "balls-1.nff";
  const Proc r = run_rtm("render " + scene + " --size 8x8 --out " + (tmp / "m.png") + " -q", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(slurp(tmp / "m.json"));
  EXPECT_EQ(j["command_line"],
            json({RTM_BINARY, "render", scene, "--size", "8x8", "--out", tmp / "m.png", "-q"}));
  EXPECT_EQ(j["scene_path"], scene);
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", (unsigned long long)rtm::fnv1a(slurp(scene)));
  EXPECT_EQ(j["scene_fnv1a"], hash);
  // The built-in scene: no file, the hash of its text (scenes/default.yaml, embedded).
  const json d = render(tmp, "d", "--size 8x8 --reference");
  ASSERT_FALSE(d.is_null());
  EXPECT_TRUE(d["scene_path"].is_null());
  std::snprintf(hash, sizeof hash, "%016llx",
                (unsigned long long)rtm::fnv1a(slurp(kSource + "scenes/default.yaml")));
  EXPECT_EQ(d["scene_fnv1a"], hash);
}

}  // namespace
