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
       "factors: {energy: {value: 0.5, source: e}, area: {value: 1, source: a}, leakage: {value: "
       "1, source: l}}\n");
  const Proc r = run_rtm("tech " + (tmp / "half.yaml"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(" 1.85 pJ "), std::string::npos) << r.out;  // fp32 multiply 3.7 x 0.5
}

TEST(Tech, ABadFileIsRefusedWithItsLineAndExit2) {
  Tmp tmp;
  spit(tmp / "bad.yaml",
       "scale_from: 45nm\n"
       "factors: {energy: {value: 1, source: e}, area: {value: 1, source: a}, leakage: {value: 1, "
       "source: l}}\n"
       "fp32_add_pj:\n"
       "  value: -1\n"
       "  source: x\n");
  const std::string bad = tmp / "bad.yaml";
  for (const std::string& args :
       {"tech " + bad, "config --set tech=" + bad,
        "render --size 4x4 -q --out " + (tmp / "x.png") + " --tech " + bad}) {
    const Proc r = run_rtm(args, tmp);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find(bad + ":4: fp32_add_pj.value: expected a number >= 0, got '-1'"),
              std::string::npos)
        << args << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(tmp / "x.png"));
  const Proc missing = run_rtm(
      "render --size 4x4 -q --out " + (tmp / "x.png") + " --tech " + (tmp / "none.yaml"), tmp);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("none.yaml:0: cannot read the technology file '"), std::string::npos)
      << missing.err;
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

namespace {

using namespace rtm::test;

const std::string kBalls = std::string(RTM_SOURCE_DIR) + "/scenes/spd/balls-1.nff --size 8x8";

// --tech moves the cost and nothing the simulation does: twice the energy per operation doubles
// every dynamic figure and leaves area, leakage and cycles alone.
TEST(Tech, ATechnologyFileChangesTheCostAndNotTheFrame) {
  Tmp tmp;
  spit(tmp / "double.yaml",
       "scale_from: 45nm\n"
       "factors: {energy: {value: 2, source: e}, area: {value: 1, source: a}, leakage: {value: 1, "
       "source: l}}\n");
  const nlohmann::json a = render(tmp, "a", kBalls),
                       b = render(tmp, "b", kBalls + " --tech " + (tmp / "double.yaml"));
  ASSERT_FALSE(a.is_null());
  ASSERT_FALSE(b.is_null());
  EXPECT_EQ(a["cycles"], b["cycles"]);
  EXPECT_EQ(a["cost"]["technology"], "45nm");
  EXPECT_EQ(b["cost"]["technology"], "double");
  EXPECT_DOUBLE_EQ(b["cost"]["area_mm2"].get<double>(), a["cost"]["area_mm2"].get<double>());
  EXPECT_DOUBLE_EQ(b["cost"]["leakage_j"].get<double>(), a["cost"]["leakage_j"].get<double>());
  ASSERT_GT(a["cost"]["dynamic_j"].get<double>(), 0);
  EXPECT_NEAR(b["cost"]["dynamic_j"].get<double>(), 2 * a["cost"]["dynamic_j"].get<double>(),
              1e-12 * a["cost"]["dynamic_j"].get<double>());
  for (const auto& [unit, figures] : a["cost"]["units"].items())
    EXPECT_NEAR(b["cost"]["units"][unit]["dynamic_j"].get<double>(),
                2 * figures["dynamic_j"].get<double>(),
                1e-12 * figures["dynamic_j"].get<double>() + 1e-30)
        << unit;
}

// The cost block adds up, and the summary repeats it.
TEST(Tech, TheCostBlockAddsUpAndTheSummaryRepeatsIt) {
  Tmp tmp;
  const nlohmann::json j = render(tmp, "s", kBalls + " --pes 2");
  ASSERT_FALSE(j.is_null());
  const nlohmann::json& c = j["cost"];
  double units = 0, logic = 0, sram = 0;
  for (const auto& [unit, f] : c["units"].items()) {
    units += f["dynamic_j"].get<double>();
    logic += f["logic_mm2"].get<double>();
    sram += f["sram_mm2"].get<double>();
  }
  const double rel = 1e-12;
  EXPECT_NEAR(c["pe_logic_mm2"].get<double>(), logic, rel * logic);
  EXPECT_NEAR(c["logic_mm2"].get<double>(), 2 * logic, rel * logic);
  EXPECT_NEAR(c["sram_mm2"].get<double>(), 2 * sram, rel * sram);
  EXPECT_NEAR(c["area_mm2"].get<double>(),
              c["logic_mm2"].get<double>() + c["sram_mm2"].get<double>() +
                  c["interconnect_mm2"].get<double>(),
              rel);
  const double dynamic =
      units + c["local_memory_dynamic_j"].get<double>() + c["link_dynamic_j"].get<double>();
  EXPECT_NEAR(c["dynamic_j"].get<double>(), dynamic, rel * dynamic);
  const double frame = c["energy_per_frame_j"].get<double>();
  EXPECT_NEAR(frame, dynamic + c["leakage_j"].get<double>(), rel * frame);
  const double seconds = j["cycles"].get<double>() * j["config"]["clock_ns"].get<double>() * 1e-9;
  EXPECT_NEAR(c["power_w"].get<double>(), frame / seconds, rel * frame / seconds);
  EXPECT_NEAR(c["energy_per_pixel_j"].get<double>(), frame / 64, rel * frame);
  const nlohmann::json& s = j["summary"];
  EXPECT_EQ(s["area_mm2"], c["area_mm2"]);
  EXPECT_EQ(s["energy_j"], c["energy_per_frame_j"]);
  EXPECT_EQ(s["power_w"], c["power_w"]);
  EXPECT_NEAR(s["frames_per_j"].get<double>(), 1 / frame, rel / frame);
  double split = s["energy_local_memory_j"].get<double>() + s["energy_link_j"].get<double>() +
                 s["energy_leakage_j"].get<double>();
  for (const auto& [unit, f] : c["units"].items()) {
    EXPECT_EQ(s["energy_" + unit + "_j"], f["dynamic_j"]) << unit;
    split += f["dynamic_j"].get<double>();
  }
  EXPECT_NEAR(split, frame, rel * frame);
  EXPECT_NEAR(s["energy_delay"].get<double>(), frame * seconds, rel * frame * seconds);
  EXPECT_NEAR(s["frames_per_s_per_mm2"].get<double>(), 1 / seconds / c["area_mm2"].get<double>(),
              rel / seconds / c["area_mm2"].get<double>());
}

}  // namespace
