// The waveform as its user sees it: GTKWave itself (Debian's gtkwave, on a virtual display from
// xvfb-run; scripts/setup installs both) opens the VCD with rtm's save file, and a Tcl script
// prints what it displays. Skipped only where either program is missing.
#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_test_support.h"

namespace {

using namespace rtm::test;

const std::string kScenes = std::string(RTM_SOURCE_DIR) + "/scenes/spd/";

// Prints each displayed signal's VCD name, each trace's shown name, and the time range in view;
// quits whatever happens, so GTKWave never waits for a user.
const char* const kScript = R"(
if {[catch {
  foreach s [gtkwave::getDisplayedSignals] { puts "signal $s" }
  for {set i 0} {$i < [gtkwave::getTotalNumTraces]} {incr i} {
    puts "trace [gtkwave::getTraceFlagsFromIndex $i] [gtkwave::getTraceNameFromIndex $i]"
  }
  puts "view [gtkwave::getWindowStartTime] [gtkwave::getWindowEndTime]"
} err]} { puts "error $err" }
gtkwave::/File/Quit
)";

bool have(const char* program) {
  return std::system(("command -v " + std::string(program) + " >/dev/null 2>&1").c_str()) == 0;
}

TEST(Gtkwave, DisplaysEveryTracedSignalUnderItsFullNameOnTheRecordedWindow) {
  if (!have("gtkwave") || !have("xvfb-run"))
    GTEST_SKIP() << "gtkwave or xvfb-run is not installed (scripts/setup installs them)";
  Tmp tmp;
  const Proc r = run_rtm(
      "render " + kScenes + "balls-1.nff --size 8x8 --pes 2 --vcd-pes 0,1 --timing clocked -q" +
          " --vcd-window pe1+100:600 --vcd " + (tmp / "w.vcd") + " --out " + (tmp / "w.png"),
      tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // no warning: the window holds work
  const std::vector<std::string> traced = vcd_signals(slurp(tmp / "w.vcd"));
  ASSERT_GT(traced.size(), 60u);  // two PEs, the MAC pipeline included

  spit(tmp / "show.tcl", kScript);
  // timeout ends GTKWave and its X server together (its process group) if it ever hangs.
  const Proc g = sh(
      "timeout -k 5 60 xvfb-run -a gtkwave -S " + (tmp / "show.tcl") + " " + (tmp / "w.gtkw"), tmp);
  ASSERT_EQ(g.exit_code, 0) << g.out << g.err;
  ASSERT_EQ(g.out.find("error "), std::string::npos) << g.out;

  std::multiset<std::string> displayed, shown;
  uint64_t view_from = 0, view_to = 0;
  std::istringstream lines(g.out);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (line.rfind("signal ", 0) == 0) displayed.insert(line.substr(7));
    if (std::regex_match(line, m, std::regex(R"(trace (\d+) (.*))")) &&
        !(std::stoul(m[1]) & 0x200))  // not a comment
      shown.insert(m[2]);
    if (std::regex_match(line, m, std::regex(R"(view (\d+) (\d+))"))) {
      view_from = std::stoull(m[1]);
      view_to = std::stoull(m[2]);
    }
  }
  // Every traced signal is displayed, once.
  EXPECT_EQ(displayed, std::multiset<std::string>(traced.begin(), traced.end())) << g.out;
  // Each under its own name: the hierarchy below the machine, not just its last part.
  EXPECT_EQ(shown.size(), traced.size());
  EXPECT_EQ(std::set<std::string>(shown.begin(), shown.end()).size(), shown.size()) << g.out;
  EXPECT_EQ(shown.count("pe1/search2/busy"), 1u) << g.out;
  EXPECT_EQ(shown.count("pe0/intersection0/mac/acc"), 1u) << g.out;

  // The view opens on the window: 500 cycles (5000 ns) from 100 cycles after PE 1 started.
  const uint64_t start =
      nlohmann::json::parse(slurp(tmp / "w.json"))["per_pe"][1]["start_cycle"].get<uint64_t>();
  EXPECT_EQ(view_from, (start + 100) * 10) << g.out;
  EXPECT_GE(view_to, (start + 600) * 10) << g.out;
  EXPECT_LE(view_to, (start + 800) * 10) << g.out;
}

}  // namespace
