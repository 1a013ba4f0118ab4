// Golden figures: every case of tb/golden/cases.txt, rendered again, must give the figures
// recorded in tb/golden/NAME.json — its statistics less what differs between runs, and hashes of
// its image, ID map and waveform — so a change meant to keep the model's behaviour can show it
// did, bit for bit. docs/machine.md, "Golden figures".
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace rtm::test;

namespace {

const std::string kGoldenDir = std::string(RTM_SOURCE_DIR) + "/tb/golden/";
const std::string kCases = kGoldenDir + "cases.txt";
/// In ARGS, the case's scratch folder (for files a case asks for, such as a waveform).
const std::string kOut = "$OUT/";
/// Set to a folder, the tests write the figures there instead of comparing
/// (scripts/golden-figures does, then shows what moved).
const char* const kWriteEnv = "RTM_GOLDEN_WRITE";

struct Case {
  std::string name;   ///< gtest-valid; the golden file is NAME.json
  std::string args;   ///< `rtm render` arguments, paths relative to the source folder
  std::string error;  ///< set instead when cases.txt cannot be used
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

/// The cases, read when the tests are registered. A malformed list gives one failing case that
/// says why, rather than stopping every test in the program.
std::vector<Case> read_cases() {
  std::ifstream f(kCases);
  if (!f) return {{"BadCaseList", "", kCases + ": cannot read it"}};
  std::vector<Case> cases;
  std::set<std::string> names;
  int n = 0;
  for (std::string line; std::getline(f, line);) {
    ++n;
    const std::string where = kCases + ":" + std::to_string(n) + ": ";
    std::istringstream words(line);
    Case c;
    if (!(words >> c.name) || c.name[0] == '#') continue;
    std::getline(words >> std::ws, c.args);
    for (char ch : c.name)
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_')
        return {{"BadCaseList", "",
                 where + "'" + c.name + "' is not a test name (letters, digits, _)"}};
    if (!names.insert(c.name).second)
      return {{"BadCaseList", "", where + "a second case named " + c.name}};
    if (c.args.empty()) return {{"BadCaseList", "", where + c.name + " has no arguments"}};
    for (const char* own : {"--out", "--stats", "--id-map", "-q"})
      if ((" " + c.args + " ").find(std::string(" ") + own + " ") != std::string::npos)
        return {{"BadCaseList", "", where + c.name + ": the test chooses " + own + " itself"}};
    cases.push_back(c);
  }
  if (cases.empty()) return {{"BadCaseList", "", kCases + ": no cases"}};
  return cases;
}

/// 64-bit FNV-1a, fed one little-endian 32-bit word at a time, so the hash does not depend on
/// the host's byte order.
class Fnv1a {
 public:
  void word(uint32_t w) {
    for (int i = 0; i < 4; ++i) byte(uint8_t(w >> (8 * i)));
  }
  void text(const std::string& s) {
    for (unsigned char c : s) byte(c);
  }
  std::string hex() const {
    char s[17];
    std::snprintf(s, sizeof s, "%016llx", (unsigned long long)h_);
    return s;
  }

 private:
  void byte(uint8_t b) { h_ = (h_ ^ b) * 1099511628211ull; }
  uint64_t h_ = 14695981039346656037ull;
};

/// Over the float RGB values as the .exr holds them, pixel by pixel, row by row.
std::string image_hash(const std::string& exr) {
  Fnv1a h;
  for (const auto& px : rtm::read_image(exr).rgb)
    for (int c = 0; c < 3; ++c) {
      const float f = float(px[c]);  // exact: the file holds floats
      uint32_t bits;
      std::memcpy(&bits, &f, sizeof bits);
      h.word(bits);
    }
  return h.hex();
}

std::string id_map_hash(const std::string& exr) {
  Fnv1a h;
  for (int32_t id : rtm::read_id_map(exr).ids) h.word(uint32_t(id));
  return h.hex();
}

/// Over the VCD text less its `$date … $end` and `$version … $end` blocks: the time of the run
/// and the SystemC build, not the model.
std::string vcd_hash(std::string vcd) {
  for (const char* block : {"$date", "$version"}) {
    const size_t from = vcd.find(block), end = vcd.find("$end", from);
    if (from != std::string::npos && end != std::string::npos) vcd.erase(from, end + 4 - from);
  }
  Fnv1a h;
  h.text(vcd);
  return h.hex();
}

/// Over the GTKWave save file less its `[dumpfile]` and `[savefile]` lines, which name the
/// scratch folder.
std::string gtkw_hash(const std::string& gtkw) {
  std::istringstream lines(gtkw);
  Fnv1a h;
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("[dumpfile]", 0) != 0 && line.rfind("[savefile]", 0) != 0) h.text(line + "\n");
  return h.hex();
}

/// The stats without what may differ between two runs of the same frame: wall times (every key
/// ending in `seconds`, at any depth), whether the reference came from the cache, the command
/// line (it names the case's scratch folder) and the build (each commit has its own).
json without_run_dependent(json j) {
  if (j.is_array())
    for (json& e : j) e = without_run_dependent(e);
  if (!j.is_object()) return j;
  for (auto it = j.begin(); it != j.end();) {
    const std::string& key = it.key();
    if (key.size() >= 7 && key.compare(key.size() - 7, 7, "seconds") == 0) {
      it = j.erase(it);
    } else {
      *it = without_run_dependent(*it);
      ++it;
    }
  }
  if (j.contains("reference") && j["reference"].is_object()) j["reference"].erase("cached");
  j.erase("command_line");
  j.erase("build");
  return j;
}

/// Renders the case in `tmp` and returns its figures (null, with a test failure, if it failed).
json figures(const Case& c, const Tmp& tmp) {
  std::string args = c.args;
  for (size_t at; (at = args.find(kOut)) != std::string::npos;)
    args.replace(at, kOut.size(), tmp / "");
  const Proc r = sh("cd '" + std::string(RTM_SOURCE_DIR) + "' && " + RTM_BINARY + " render " +
                        args + " --out " + (tmp / "image.exr") + " --id-map " + (tmp / "id.exr") +
                        " --stats " + (tmp / "stats.json") + " -q",
                    tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return nullptr;
  json j = without_run_dependent(json::parse(slurp(tmp / "stats.json")));
  j["image_fnv1a"] = image_hash(tmp / "image.exr");
  j["id_map_fnv1a"] = id_map_hash(tmp / "id.exr");
  std::vector<fs::path> vcds;
  for (const auto& e : fs::directory_iterator(tmp / ""))
    if (e.path().extension() == ".vcd") vcds.push_back(e.path());
  EXPECT_LE(vcds.size(), 1u) << c.name << ": one waveform per case";
  if (!vcds.empty()) {
    j["vcd_fnv1a"] = vcd_hash(slurp(vcds[0]));
    j["gtkw_fnv1a"] = gtkw_hash(slurp(fs::path(vcds[0]).replace_extension(".gtkw")));
  }
  return j;
}

/// Each leaf of `golden` that `now` lacks or holds differently, as "path: golden G, now N".
/// Keys only in `now` are allowed (later work adds statistics); arrays must keep their length.
/// Leaves compare as JSON text: doubles print as the shortest text that reads back the same, so
/// equal text is equal bits.
void differences(const json& golden, const json& now, const std::string& path,
                 std::vector<std::string>& out) {
  const std::string at = path.empty() ? "(top)" : path;
  if (golden.is_object() && now.is_object()) {
    for (const auto& [key, value] : golden.items()) {
      const std::string p = path.empty() ? key : path + "." + key;
      if (now.contains(key))
        differences(value, now[key], p, out);
      else
        out.push_back(p + ": golden " + value.dump() + ", now missing");
    }
  } else if (golden.is_array() && now.is_array()) {
    if (golden.size() != now.size())
      out.push_back(at + ": golden " + std::to_string(golden.size()) + " elements, now " +
                    std::to_string(now.size()));
    for (size_t i = 0; i < std::min(golden.size(), now.size()); ++i)
      differences(golden[i], now[i], path + "[" + std::to_string(i) + "]", out);
  } else if (golden.dump() != now.dump()) {
    out.push_back(at + ": golden " + golden.dump() + ", now " + now.dump());
  }
}

class Figures : public ::testing::TestWithParam<Case> {};

TEST_P(Figures, Unchanged) {
  const Case& c = GetParam();
  if (!c.error.empty()) FAIL() << c.error;
  Tmp tmp;
  const json now = figures(c, tmp);
  ASSERT_FALSE(now.is_null()) << c.args;

  if (const char* dir = std::getenv(kWriteEnv); dir && *dir) {
    rtm::write_text_atomically((fs::path(dir) / (c.name + ".json")).string(), now.dump(2) + "\n");
    return;
  }
  const std::string file = kGoldenDir + c.name + ".json";
  if (!fs::exists(file))
    FAIL() << "no golden figures for " << c.name << " (" << file
           << "); record them with scripts/golden-figures " << c.name;
  const json golden = json::parse(slurp(file));
  std::vector<std::string> diffs;
  differences(golden, now, "", diffs);
  if (diffs.empty()) return;
  std::ostringstream report;
  constexpr size_t kShown = 20;
  for (size_t i = 0; i < std::min(diffs.size(), kShown); ++i) report << "  " << diffs[i] << "\n";
  if (diffs.size() > kShown) report << "  … and " << diffs.size() - kShown << " more\n";
  ADD_FAILURE() << c.name << " (" << c.args << "): " << diffs.size() << " figure(s) differ from "
                << file << ":\n"
                << report.str()
                << "If the change is meant, regenerate with scripts/golden-figures and say in the "
                   "commit why each moved.";
}

INSTANTIATE_TEST_SUITE_P(Golden, Figures, ::testing::ValuesIn(read_cases()),
                         [](const ::testing::TestParamInfo<Case>& i) { return i.param.name; });

/// A golden file without a case would never be checked again.
TEST(GoldenFiles, EachBelongsToACase) {
  std::set<std::string> names;
  for (const Case& c : read_cases()) {
    if (!c.error.empty()) FAIL() << c.error;
    names.insert(c.name);
  }
  for (const auto& e : fs::directory_iterator(kGoldenDir)) {
    if (e.path().extension() != ".json") continue;
    EXPECT_TRUE(names.count(e.path().stem().string()))
        << e.path() << " has no case in " << kCases << ": remove it, or add the case back";
  }
}

}  // namespace
