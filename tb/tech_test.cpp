// Whole-program tests of the technology: `rtm tech`, `--tech` and the `tech` key.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"

namespace {

using namespace rtm::test;

const std::string kTechFile = std::string(RTM_SOURCE_DIR) + "/model/cost/tech/45nm.yaml";

TEST(Tech, PrintsEveryEntryWithValueUnitAndSource) {
  Tmp tmp;
  const Proc r = run_rtm("tech", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("technology 45nm from <built-in 45nm>"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fp32_mul_pj"), std::string::npos);
  EXPECT_NE(r.out.find(" 3.7 pJ "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Horowitz"), std::string::npos);
  // The repository's file reads the same as the built-in one.
  const Proc file = run_rtm("tech " + kTechFile, tmp);
  ASSERT_EQ(file.exit_code, 0) << file.err;
  EXPECT_EQ(file.out.substr(file.out.find('\n')), r.out.substr(r.out.find('\n')));
}

TEST(Tech, ADerivedFilePrintsItsScaledFigures) {
  Tmp tmp;
  spit(tmp / "half.yaml",
       "scale_from: 45nm\n"
       "factors: {energy: {value: 0.5, source: e}, area: {value: 1, source: a}, leakage: {value: 1, source: l}}\n");
  const Proc r = run_rtm("tech " + (tmp / "half.yaml"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(" 1.85 pJ "), std::string::npos) << r.out;  // fp32 multiply 3.7 x 0.5
}

TEST(Tech, ABadFileIsRefusedWithItsLineAndExit2) {
  Tmp tmp;
  spit(tmp / "bad.yaml",
       "scale_from: 45nm\n"
       "factors: {energy: {value: 1, source: e}, area: {value: 1, source: a}, leakage: {value: 1, source: l}}\n"
       "fp32_add_pj:\n"
       "  value: -1\n"
       "  source: x\n");
  const std::string bad = tmp / "bad.yaml";
  for (const std::string& args : {"tech " + bad, "config --set tech=" + bad,
                                  "render --size 4x4 -q --out " + (tmp / "x.png") + " --tech " + bad}) {
    const Proc r = run_rtm(args, tmp);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find(bad + ":4: fp32_add_pj.value: expected a number >= 0, got '-1'"), std::string::npos)
        << args << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(tmp / "x.png"));
  const Proc missing = run_rtm("render --size 4x4 -q --out " + (tmp / "x.png") + " --tech " + (tmp / "none.yaml"), tmp);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("none.yaml:0: cannot read the technology file '"), std::string::npos) << missing.err;
}

TEST(Tech, RenderTakesTheFileAndTheStatsRecordIt) {
  Tmp tmp;
  const nlohmann::json s = render(tmp, "t", "--size 8x8 --tech " + kTechFile);
  ASSERT_FALSE(s.is_null());
  EXPECT_EQ(s["config"]["tech"], kTechFile);
  const nlohmann::json d = render(tmp, "d", "--size 8x8");
  ASSERT_FALSE(d.is_null());
  EXPECT_EQ(d["config"]["tech"], "45nm");
}

}  // namespace
