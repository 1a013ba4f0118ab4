// Reliability of the whole program (docs/reliability.md): every accepted input finishes or is
// refused up front with exit 2, error figures that cannot lie, a checked reference cache, and
// interrupted runs that leave nothing half-written under a final name.
#include <string>
#include <vector>

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
      {"render --grid 2000", "--grid"},               // 8e9 voxels (was exit 1)
      {"render --grid 4000x4000x2", "--grid"},
      {"render --size 20000x10", "--size"},           // past the 16384 a side scenes allow (was exit 1)
      {"render --pes 0", "--pes"},
      {"render --threshold 2", "--threshold"},
      {"render --no-such-option", "--no-such-option"},
      {"render --pes", "--pes"},                      // a missing value
      {"", "subcommand"},                             // no command at all
      {"frobnicate", "subcommand"},
  };
  for (const UsageCase& c : cases) {
    Tmp tmp;
    const Proc r = run_rtm(std::string(c.args) + " --out " + (tmp / "o.png") + " -q", tmp);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
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

}  // namespace
