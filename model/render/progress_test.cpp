#include "render/progress.h"

#include <gtest/gtest.h>

namespace rtm {
namespace {

TEST(Progress, OneMeasureWithElapsedTimeRateAndTimeLeft) {
  Progress p;
  p.phase = "PEs";
  p.pixels_started = 4096;
  p.pixels = 16384;
  p.seconds = 8;
  p.resident_bytes = uint64_t(3) << 29;
  // 512 pixels a second: the other 12288 take 24 s.
  EXPECT_EQ(progress_line(p),
            "PEs: at pixel 4096/16384 (25.0%), 8.0 s, 512 px/s, ETA 24.0 s, 1.50 GiB");
  p.seconds = 80;
  EXPECT_EQ(progress_line(p),
            "PEs: at pixel 4096/16384 (25.0%), 1m20s, 51 px/s, ETA 4m00s, 1.50 GiB");
}

TEST(Progress, BeforeThePesStartThereIsNoRate) {
  Progress p;
  p.phase = "transfer";
  p.pixels = 100;
  p.seconds = 1.25;
  EXPECT_EQ(progress_line(p), "transfer: at pixel 0/100 (0.0%), 1.2 s");
}

// The reference's line: a pixel whose ray tree grows shows no pixel rate, but its rays.
TEST(Progress, TheReferenceAddsTheRaysTraced) {
  Progress p;
  p.phase = "reference";
  p.pixels = 1;
  p.seconds = 3;
  p.rays = 123456789;
  p.resident_bytes = uint64_t(1) << 27;
  EXPECT_EQ(progress_line(p), "reference: at pixel 0/1 (0.0%), 3.0 s, 1.23e+08 rays, 0.12 GiB");
}

TEST(Progress, BudgetsAreInMibBelowAGibibyte) {
  EXPECT_EQ(bytes_text(uint64_t(220) << 20), "220.0 MiB");
  EXPECT_EQ(bytes_text(uint64_t(3) << 29), "1.50 GiB");
}

TEST(Progress, TheResidentSizeIsRead) {
  EXPECT_GT(resident_bytes(), uint64_t(1) << 20);  // a test program holds more than a megabyte
}

// A host step counts what it does, with its time left but no rate; one it cannot count shows its
// time.
TEST(Progress, AHostStepCountsItsItems) {
  Progress p;
  p.phase = "voxelisation";
  p.item = "primitive";
  p.pixels_started = 250000;
  p.pixels = 1000000;
  p.seconds = 0.5;
  p.resident_bytes = uint64_t(3) << 29;
  EXPECT_EQ(progress_line(p),
            "voxelisation: at primitive 250000/1000000 (25.0%), 0.5 s, ETA 1.5 s, 1.50 GiB");
  p.phase = "mesh import (Assimp)";
  p.item = "";
  p.pixels_started = p.pixels = 0;
  p.seconds = 2;
  EXPECT_EQ(progress_line(p), "mesh import (Assimp): 2.0 s, 1.50 GiB");
}

/// What a StepLine wrote, read back from its file.
std::string written(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  for (int c; (c = std::fgetc(f)) != EOF;) s += char(c);
  return s;
}

TEST(StepLine, DrawsTheStepThenErasesItAndIsSilentWhenDisabled) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    StepLine line(true, f, std::chrono::milliseconds(0));
    line("grid build", "", 0, 0);
    line("grid build", "", 0, 0);  // within half a second of the last: not drawn again
    const std::string s = written(f);
    EXPECT_EQ(s.rfind("\rgrid build: 0.0 s", 0), 0u) << s;
    EXPECT_EQ(s.size(), 80u) << s;  // one line, padded to 79 characters
  }
  EXPECT_EQ(written(f).substr(80), "\r" + std::string(80, ' ') + "\r");  // erased at the end
  std::fclose(f);

  std::FILE* g = std::tmpfile();
  {
    StepLine quiet(false, g, std::chrono::milliseconds(0));
    quiet("voxelisation", "primitive", 1, 2);
    StepLine early(true, g);  // its first second: nothing yet
    early("voxelisation", "primitive", 1, 2);
  }
  EXPECT_EQ(written(g), "");
  std::fclose(g);
}

TEST(Progress, TheLineFitsATerminal) {
  Progress p;
  p.phase = "PEs";
  p.pixels_started = 123456789;
  p.pixels = 268435456;
  p.seconds = 99999;
  p.rays = ~uint64_t(0);
  p.resident_bytes = uint64_t(1) << 40;
  EXPECT_LE(progress_line(p).size(), 79u);
}

}  // namespace
}  // namespace rtm
