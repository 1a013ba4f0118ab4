// The proof of docs/architecture.md, "Adding a unit": a unit added through the tables alone (its
// class, pass_through.h; its rows, pass_through.def) runs under both schedulers, the PE engine and
// the SystemC modules, and they write the same event log. This program is built with the units,
// the engine and the machine compiled again with the unit in (CMakeLists.txt,
// rtm_test_unit_tests); the normal build has no such unit. SystemC elaborates once per process:
// each scheduler runs the frame in a process of its own. The plain driver of the engine's tests
// (engine/cycle_driver.h) runs it too.
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <systemc>

#include "engine/test_pe.h"
#include "geom/grid.h"
#include "machine/machine.h"
#include "scene/scene.h"
#include "test_unit/pass_through.h"

namespace rtm {
namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Renders a small frame of balls-1 in a child process, the PEs on the engine or as modules;
/// returns its event log, and in `summary` its cycles, why the engine did not run ("" if it did)
/// and the image's pixels.
std::string render(bool modules, std::string& summary) {
  const std::string base = ::testing::TempDir() + "pass_through_" + std::to_string(getpid()) + "_" +
                           (modules ? "modules" : "engine");
  const pid_t child = fork();
  if (child == 0) {
    Scene scene = load_scene(std::string(RTM_SOURCE_DIR) + "/scenes/spd/balls-1.nff");
    scene.camera.width = scene.camera.height = 16;
    const Grid grid = build_grid(scene.primitives, scene.grid, 1);
    MachineConfig c;
    c.pe_simulation =
        modules ? MachineConfig::PeSimulation::Modules : MachineConfig::PeSimulation::Auto;
    c.search_units = 2;
    MachineOptions opt;
    opt.event_log = base + ".log";
    opt.sim_threads = 1;
    const MachineResult m = run_machine(scene, grid, c, opt);
    std::ofstream out(base + ".summary");
    out << "cycles " << m.cycles << "\nengine_unsupported '" << m.engine_unsupported << "'\n";
    out.precision(17);
    for (size_t i = 0; i < m.image.rgb.size(); ++i)
      out << m.image.rgb[i].x << " " << m.image.rgb[i].y << " " << m.image.rgb[i].z << " "
          << m.image.ids[i] << "\n";
    out.close();
    _exit(m.deadlock ? 3 : 0);
  }
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
  summary = read(base + ".summary");
  return read(base + ".log");
}

/// An event-log line's fields.
struct Event {
  uint64_t cycle;
  std::string pe, unit, ray, what, detail;
};
std::vector<Event> parse(const std::string& log) {
  std::vector<Event> events;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);) {
    std::istringstream l(line);
    Event e;
    l >> e.cycle >> e.pe >> e.unit >> e.ray >> e.what;
    std::getline(l >> std::ws, e.detail);
    events.push_back(e);
  }
  return events;
}

TEST(TestUnit, BothSchedulersRunAPassThroughAddedThroughTheTables) {
  std::string engine_summary, modules_summary;
  const std::string engine = render(false, engine_summary);
  const std::string modules = render(true, modules_summary);
  ASSERT_NE(engine_summary.find("engine_unsupported ''"), std::string::npos) << engine_summary;
  ASSERT_NE(modules_summary.find("engine_unsupported 'pe_simulation = modules'"), std::string::npos)
      << modules_summary.substr(0, 200);
  EXPECT_FALSE(engine.empty());
  EXPECT_TRUE(engine == modules) << "the event logs differ";
  // Same cycles and picture (the summaries differ only in why the engine did not run).
  EXPECT_EQ(engine_summary.substr(0, engine_summary.find('\n')),
            modules_summary.substr(0, modules_summary.find('\n')));
  EXPECT_EQ(engine_summary.substr(engine_summary.find('\n', engine_summary.find('\n') + 1)),
            modules_summary.substr(modules_summary.find('\n', modules_summary.find('\n') + 1)));

  // The stage does its job: every ray the search units send to intersection passes through it,
  // held its cycles, on to the intersection units, in order; nothing skips it.
  std::map<std::string, std::vector<uint64_t>> sent, taken, handed;  // by PE and ray
  for (const Event& e : parse(engine)) {
    const std::string ray = e.pe + " " + e.ray;
    if (e.unit.rfind("search", 0) == 0 && e.what == "put") {
      EXPECT_NE(e.detail, "intersect_fifo") << "a ray skipped the pass-through stage";
      if (e.detail == "pass_fifo") sent[ray].push_back(e.cycle);
    }
    if (e.unit == "pass_through" && e.what == "take") {
      EXPECT_EQ(e.detail, std::to_string(PassThroughUnit::kCycles));
      taken[ray].push_back(e.cycle);
    }
    if (e.unit == "pass_through" && e.what == "put") {
      EXPECT_EQ(e.detail, "intersect_fifo");
      handed[ray].push_back(e.cycle);
    }
  }
  EXPECT_GT(sent.size(), 10u);
  EXPECT_EQ(taken.size(), sent.size());
  EXPECT_EQ(handed.size(), sent.size());
  for (const auto& [ray, at] : sent) {
    ASSERT_EQ(taken[ray].size(), at.size()) << ray;
    ASSERT_EQ(handed[ray].size(), at.size()) << ray;
    for (size_t i = 0; i < at.size(); ++i) {
      EXPECT_GE(taken[ray][i], at[i]) << ray;
      EXPECT_GE(handed[ray][i], taken[ray][i] + PassThroughUnit::kCycles) << ray;
    }
  }
}

TEST(TestUnit, ThePlainDriverRunsItAsTheEngineDoes) {
  MachineConfig c;
  c.search_units = 2;
  test::EnginePe engine("balls-1", 8, c), driver("balls-1", 8, c);
  const std::vector<std::string> a = engine.run(), b = driver.run_cycle_driver();
  EXPECT_TRUE(a == b) << "the event logs differ";
  EXPECT_GT(engine.pe.counters.total(UnitKind::PassThrough).items, 100u);
  EXPECT_EQ(engine.pe.counters.total(UnitKind::PassThrough).items,
            driver.pe.counters.total(UnitKind::PassThrough).items);
}

}  // namespace
}  // namespace rtm

int sc_main(int argc, char* argv[]) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
