#include "cost/technology.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace rtm {
namespace {

const std::string kTechFile = std::string(RTM_SOURCE_DIR) + "/model/cost/tech/45nm.yaml";

std::string file_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// The 1-based line of the first occurrence of `what` in `text`.
int line_of(const std::string& text, const std::string& what) {
  const size_t at = text.find(what);
  EXPECT_NE(at, std::string::npos) << what;
  return 1 + int(std::count(text.begin(), text.begin() + at, '\n'));
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

/// The message parsing `text` as t.yaml gives, "" if it parses.
std::string refusal(const std::string& text) {
  try {
    parse_technology(text, "t.yaml");
  } catch (const TechnologyError& e) {
    return e.what();
  }
  return "";
}

TEST(Technology, TheBuiltInIsTheRepositorysFile) {
  const Technology built_in = load_technology(kBuiltInTechnology);
  const Technology file = load_technology(kTechFile);
  EXPECT_EQ(built_in.name, "45nm");
  for (const TechEntry& e : technology_entries()) {
    EXPECT_EQ((built_in.*e.member).value, (file.*e.member).value) << e.name;
    EXPECT_FALSE((built_in.*e.member).source.empty()) << e.name;
  }
}

TEST(Technology, ReadsHorowitzsFiguresAndTheirSources) {
  const Technology t = load_technology(kBuiltInTechnology);
  EXPECT_EQ(t.fp32_add_pj.value, 0.9);
  EXPECT_EQ(t.fp32_mul_pj.value, 3.7);
  EXPECT_EQ(t.fp32_mul_um2.value, 7700);
  EXPECT_EQ(t.int32_add_um2.value, 137);
  EXPECT_NE(t.fp32_add_pj.source.find("Horowitz"), std::string::npos);
  EXPECT_NE(t.fp64_mul_pj.source.find("assumption"), std::string::npos);
}

TEST(Technology, Fp32MacProductIsTheTablesMultiplyPlusAdd) {
  const Technology t = load_technology(kBuiltInTechnology);
  EXPECT_DOUBLE_EQ(mac_product_energy_pj(t, Precision::Fp32), 3.7 + 0.9);
  EXPECT_DOUBLE_EQ(mac_product_energy_pj(t, Precision::Fp64),
                   t.fp64_mul_pj.value + t.fp64_add_pj.value);
  EXPECT_GT(mac_product_energy_pj(t, Precision::Fp64), mac_product_energy_pj(t, Precision::Fp32));
}

// The SRAM model is fitted to Horowitz's 8 KB and 32 KB reads (ISSCC 2014). Checked on his 1 MB
// read, 100 pJ for 64 bits, which the fit does not use.
TEST(Technology, SramModelPredictsAHeldOutSizeWithin20Percent) {
  const Technology t = load_technology(kBuiltInTechnology);
  EXPECT_DOUBLE_EQ(sram_access_energy_pj(t, 8 << 10, 64), 10);
  EXPECT_NEAR(sram_access_energy_pj(t, 32 << 10, 64), 20, 1e-9);
  const double one_mb = sram_access_energy_pj(t, 1 << 20, 64);
  EXPECT_NEAR(one_mb, 100, 20) << one_mb;
  EXPECT_DOUBLE_EQ(sram_access_energy_pj(t, 8 << 10, 32), 5);  // linear in the bits moved
  EXPECT_DOUBLE_EQ(sram_area_um2(t, 8 << 10), 8 * 8192 * t.sram_bit_um2.value);
}

TEST(Technology, ADerivedNodeFollowsItsFactors) {
  const Technology base = load_technology(kBuiltInTechnology);
  const Technology t = parse_technology(
      "name: small\n"
      "scale_from: 45nm\n"
      "factors:\n"
      "  energy: {value: 0.5, source: e}\n"
      "  area: {value: 0.25, source: a}\n"
      "  leakage: {value: 2, source: l}\n"
      "dram_read_bit_pj: {value: 7, source: own}\n",
      "small.yaml");
  EXPECT_EQ(t.name, "small");
  EXPECT_DOUBLE_EQ(t.fp32_mul_pj.value, base.fp32_mul_pj.value * 0.5);
  EXPECT_DOUBLE_EQ(t.fp32_mul_um2.value, base.fp32_mul_um2.value * 0.25);
  EXPECT_DOUBLE_EQ(t.sram_bit_um2.value, base.sram_bit_um2.value * 0.25);
  EXPECT_DOUBLE_EQ(t.logic_leakage_nw_per_um2.value, base.logic_leakage_nw_per_um2.value * 2);
  EXPECT_EQ(t.sram_bytes.value, base.sram_bytes.value);  // sizes are not scaled
  EXPECT_EQ(t.sram_energy_exponent.value, base.sram_energy_exponent.value);
  EXPECT_EQ(t.dram_read_bit_pj.value, 7);
  EXPECT_EQ(t.dram_read_bit_pj.source, "own");
  EXPECT_NE(t.fp32_mul_pj.source.find("x 0.5 (e)"), std::string::npos) << t.fp32_mul_pj.source;
}

TEST(Technology, ADerivedFileFindsItsBaseBesideIt) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("rtm-tech-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(kTechFile, dir / "base.yaml",
                             std::filesystem::copy_options::overwrite_existing);
  const std::string factors =
      "factors: {energy: {value: 2, source: e}, area: {value: 1, source: a}, leakage: {value: 1, "
      "source: l}}\n";
  std::ofstream(dir / "derived.yaml") << "scale_from: base.yaml\n" << factors;
  std::ofstream(dir / "loop.yaml") << "scale_from: loop.yaml\n" << factors;
  EXPECT_DOUBLE_EQ(load_technology((dir / "derived.yaml").string()).fp32_add_pj.value, 1.8);
  try {
    load_technology((dir / "loop.yaml").string());
    ADD_FAILURE() << "a file scaling from itself was read";
  } catch (const TechnologyError& e) {
    EXPECT_NE(std::string(e.what()).find("scale from itself"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

struct BadFile {
  const char* what;
  std::string from, to;  ///< the change to the repository's file
  std::string at;        ///< the text whose line the message names (in the changed file)
  const char* message;
};

TEST(Technology, BadFilesAreRefusedWithTheirLine) {
  const std::string good = file_text(kTechFile);
  ASSERT_EQ(refusal(good), "");
  const std::vector<BadFile> cases = {
      {"negative", "  value: 3.7\n", "  value: -3.7\n", "  value: -3.7",
       "fp32_mul_pj.value: expected a number >= 0, got '-3.7'"},
      {"NaN", "  value: 3.7\n", "  value: nan\n", "  value: nan",
       "fp32_mul_pj.value: expected a finite number, got 'nan'"},
      {"not a number", "  value: 3.7\n", "  value: lots\n", "  value: lots",
       "fp32_mul_pj.value: expected a number, got 'lots'"},
      {"wrong type", "  value: 3.7\n", "  value: [3.7]\n", "  value: [3.7]",
       "fp32_mul_pj.value: expected a number"},
      {"entry not a map",
       "fp32_mul_um2:\n  value: 7700\n  source: \"Horowitz, ISSCC 2014: fp32 multiplier area, 45 "
       "nm\"\n",
       "fp32_mul_um2: 7700\n", "fp32_mul_um2: 7700",
       "fp32_mul_um2: expected {value: NUMBER, source: TEXT}"},
      {"unknown key",
       "fp32_mul_pj:", "fp32_mult_pj:", "fp32_mult_pj:", "unknown key 'fp32_mult_pj'"},
      {"missing source",
       "fp32_mul_um2:\n  value: 7700\n  source: \"Horowitz, ISSCC 2014: fp32 multiplier area, 45 "
       "nm\"\n",
       "fp32_mul_um2:\n  value: 7700\n", "  value: 7700", "fp32_mul_um2: missing 'source'"},
      {"zero size", "  value: 8192\n", "  value: 0\n", "  value: 0\n",
       "sram_bytes.value: expected a number > 0, got '0'"},
      {"syntax", "fp32_mul_pj:\n", "fp32_mul_pj: [\n", "fp32_mul_pj: [", "YAML syntax error"},
  };
  for (const BadFile& c : cases) {
    const std::string text = replaced(good, c.from, c.to);
    const std::string m = refusal(text);
    EXPECT_NE(m.find(c.message), std::string::npos) << c.what << ": " << m;
    if (std::string(c.what) != "syntax")
      EXPECT_EQ(m.rfind("t.yaml:" + std::to_string(line_of(text, c.at)) + ": ", 0), 0u)
          << c.what << ": " << m;
    else
      EXPECT_EQ(m.rfind("t.yaml:", 0), 0u) << m;
  }
  // A missing entry names it, at the top of the file.
  const std::string missing = replaced(good, "fp32_add_pj:\n  value: 0.9\n", "");
  const std::string m =
      refusal(replaced(missing, "  source: \"Horowitz, ISSCC 2014: fp32 add, 45 nm\"\n", ""));
  EXPECT_NE(m.find("t.yaml:" + std::to_string(line_of(good, "name: 45nm")) +
                   ": missing entry 'fp32_add_pj'"),
            std::string::npos)
      << m;
}

TEST(Technology, AnUnreadableFileIsNamed) {
  try {
    load_technology("no/such/tech.yaml");
    FAIL();
  } catch (const TechnologyError& e) {
    EXPECT_EQ(std::string(e.what()),
              "no/such/tech.yaml:0: cannot read the technology file 'no/such/tech.yaml'");
  }
}

TEST(Technology, AFileTooLargeToBeOneIsNotRead) {
  const std::string path = std::filesystem::temp_directory_path() /
                           ("rtm-tech-big-" + std::to_string(getpid()) + ".yaml");
  std::ofstream(path) << std::string((1 << 20) + 1, '#');
  try {
    load_technology(path);
    ADD_FAILURE() << "a 1 MiB + 1 file was read";
  } catch (const TechnologyError& e) {
    EXPECT_NE(std::string(e.what()).find("1048577 bytes: not a technology file"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

TEST(Technology, DescribeListsEveryEntryWithUnitAndSource) {
  const Technology t = load_technology(kBuiltInTechnology);
  const std::string d = describe_technology(t);
  for (const TechEntry& e : technology_entries()) {
    std::istringstream lines(d);
    std::string line;
    bool found = false;
    while (std::getline(lines, line))
      found = found || (line.rfind(std::string(e.name) + " ", 0) == 0 &&
                        line.find(std::string(" ") + e.unit + " ") != std::string::npos &&
                        line.find((t.*e.member).source) != std::string::npos);
    EXPECT_TRUE(found) << e.name;
  }
}

}  // namespace
}  // namespace rtm
