// The committed fuzz corpus (tb/fuzz-corpus/TARGET: what scripts/fuzz --merge kept, the fewest
// inputs covering the most, and any that once broke a reader), replayed through the fuzz targets'
// own entry functions in this build: each input is read or refused with its reader's error, never
// another exception, and well within the fuzzers' limit of 1 s.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "fuzz/entries.h"

namespace rtm::fuzz {

void PrintTo(const Target& t, std::ostream* os) { *os << t.name; }

namespace {

class FuzzCorpus : public ::testing::TestWithParam<Target> {};

TEST_P(FuzzCorpus, EveryInputIsReadOrRefusedWithinASecond) {
  const Target& target = GetParam();
  const std::filesystem::path dir =
      std::filesystem::path(RTM_SOURCE_DIR) / "tb" / "fuzz-corpus" / target.name;
  int read = 0, refused = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    SCOPED_TRACE(entry.path().string());
    std::ifstream f(entry.path(), std::ios::binary);
    std::ostringstream text;
    text << f.rdbuf();
    const auto t0 = std::chrono::steady_clock::now();
    bool accepted = false;
    EXPECT_NO_THROW(accepted = target.run(text.str()));
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
    ++(accepted ? read : refused);
  }
  // Both outcomes, so that a reader refusing everything (or nothing) shows here.
  EXPECT_GT(read, 0) << dir;
  EXPECT_GT(refused, 0) << dir;
  std::printf("%s: %d inputs read, %d refused\n", target.name, read, refused);
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzCorpus, ::testing::ValuesIn(kTargets),
                         [](const ::testing::TestParamInfo<Target>& p) {
                           return std::string(p.param.name);
                         });

}  // namespace
}  // namespace rtm::fuzz
