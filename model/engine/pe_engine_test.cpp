// The PE engine in process, without SystemC, on hand-built PE states (one PE of an SPD scene, its
// primary rays handed over at once): every ray tree finishes and sums to the pixel the units give
// traced one ray at a time; back-to-back items; a full FIFO stalling shading; credits bounding
// the rays past the front buffer; spills beyond the on-chip capacity; and the same frames on a
// second, plain driver of the same units (engine/cycle_driver.h) write the same event logs.
// tb/engine_test.cpp compares the engine with the modules on whole frames.
#include "engine/pe_engine.h"

#include "engine/test_pe.h"

#include <algorithm>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "error/pe_tracer.h"

namespace rtm {
namespace {
using test::EnginePe;
using test::kCycle;

/// An event-log line's fields: cycle, unit, ray, event, detail.
struct Event {
  uint64_t cycle;
  std::string unit, ray, what, detail;
};
Event parse(const std::string& line) {
  std::istringstream in(line);
  Event e;
  std::string pe;
  in >> e.cycle >> pe >> e.unit >> e.ray >> e.what;
  std::getline(in >> std::ws, e.detail);
  return e;
}

MachineConfig fast() {
  MachineConfig c;
  c.search_units = 2;
  return c;
}

/// What the units give each pixel, each ray traced one at a time depth first (error/pe_tracer.h).
std::vector<PixelSum> traced_one_at_a_time(const EnginePe& p) {
  PeTracer tracer(p.view.scene, p.view.grid, p.pe.config);
  std::vector<PixelSum> frame(p.rays.size());
  for (size_t i = 0; i < p.rays.size(); ++i) {
    std::vector<Ray> todo{p.rays[i]};
    while (!todo.empty()) {
      const Ray r = todo.back();
      todo.pop_back();
      RayResult out;
      tracer.trace(r, out);
      frame[i].add(out.added);
      todo.insert(todo.end(), out.spawned.begin(), out.spawned.end());
    }
  }
  return frame;
}

bool same(const std::vector<PixelSum>& a, const std::vector<PixelSum>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](const PixelSum& x, const PixelSum& y) { return x.q == y.q; });
}

TEST(PeEngine, EveryRayTreeFinishesAndSumsToItsPixelTracedOneRayAtATime) {
  EnginePe p("balls-1", 8, fast());
  const std::vector<std::string> log = p.run();
  EXPECT_TRUE(same(p.frame, traced_one_at_a_time(p)));
  EXPECT_EQ(p.pe.counters.counts.rays[size_t(RayKind::Primary)], 64u);
  EXPECT_GT(p.pe.counters.counts.rays[size_t(RayKind::Shadow)], 0u);
  // Each ray the front buffer hands out the first time ends once; nothing happens after the finish.
  std::map<std::string, int> taken, ended;
  for (const std::string& line : log) {
    const Event e = parse(line);
    EXPECT_LE(e.cycle * kCycle, p.pe.counters.finish) << line;
    if (e.unit == "front_buffer" && e.what == "take" &&
        e.detail.find("primary") != std::string::npos)
      ++taken[e.ray];
    if (e.what == "put" && e.detail == "ends_fifo") ++ended[e.ray];
  }
  EXPECT_EQ(taken.size(), 64u);
  for (const auto& [ray, n] : ended) EXPECT_EQ(n, 1) << ray;
  EXPECT_EQ(ended.size(), size_t(p.pe.counters.counts.total_rays()));
}

TEST(PeEngine, APipelinedFrontBufferHandsOutRaysBackToBack) {
  for (int interval : {1, 0}) {
    MachineConfig c = fast();
    c.fb_dispatch_cycles = 3;
    c.dispatch_interval = interval;  // 0: unpipelined, each ray its own 3 cycles
    EnginePe p("balls-1", 4, c);
    std::vector<uint64_t> takes;
    for (const std::string& line : p.run()) {
      const Event e = parse(line);
      if (e.unit == "front_buffer" && e.what == "take") takes.push_back(e.cycle);
    }
    ASSERT_GE(takes.size(), 4u);
    for (size_t i = 1; i < 4; ++i)
      EXPECT_EQ(takes[i] - takes[i - 1], interval ? 1u : 3u) << "interval " << interval;
  }
}

/// The cycles at which shading wrote each ray's spawned rays, per shaded ray.
std::map<std::string, std::vector<uint64_t>> spawn_puts(const std::vector<std::string>& log) {
  std::map<std::string, std::vector<uint64_t>> puts;
  std::string parent;
  for (const std::string& line : log) {
    const Event e = parse(line);
    if (e.unit != "shading" || e.what != "put") continue;
    if (e.detail == "ends_fifo") parent = e.ray;  // a ray's end comes first, then its spawned rays
    if (e.detail == "spawn_fifo") puts[parent].push_back(e.cycle);
  }
  return puts;
}

TEST(PeEngine, AFullSpawnFifoStallsShading) {
  MachineConfig deep = fast(), shallow = fast();
  shallow.feedback_fifo_depth =
      1;  // one spawned ray at a time: the next waits for the front buffer to read it
  EnginePe a("balls-1", 8, deep), b("balls-1", 8, shallow);
  const auto wide = spawn_puts(a.run()), narrow = spawn_puts(b.run());
  EXPECT_TRUE(same(a.frame, b.frame));
  bool together = false, several = false;
  for (const auto& [ray, cycles] : wide)
    together = together || (cycles.size() > 1 && cycles.front() == cycles.back());
  for (const auto& [ray, cycles] : narrow) {
    several = several || cycles.size() > 1;
    for (size_t i = 1; i < cycles.size(); ++i) EXPECT_GT(cycles[i], cycles[i - 1]) << ray;
  }
  EXPECT_TRUE(together) << "with room, a ray's spawned rays leave in one cycle";
  EXPECT_TRUE(several);
  EXPECT_GT(b.pe.counters.total(UnitKind::Shading).held_cycles,
            a.pe.counters.total(UnitKind::Shading).held_cycles);
}

TEST(PeEngine, CreditsBoundTheRaysPastTheFrontBuffer) {
  MachineConfig c = fast();
  c.loop_credits = 2;
  EnginePe p("balls-1", 8, c);
  // A ray takes a credit when handed out and returns it when fed back or ended. The log lists the
  // front buffer first within a cycle, but a credit returned in a cycle may be taken again in it:
  // each cycle's returns count first.
  std::map<uint64_t, std::pair<int, int>> per_cycle;  // returns, takes
  for (const std::string& line : p.run()) {
    const Event e = parse(line);
    if (e.unit == "front_buffer" && e.what == "take") ++per_cycle[e.cycle].second;
    if (e.what == "put" && (e.detail == "ends_fifo" || e.detail.rfind("feedback_", 0) == 0))
      ++per_cycle[e.cycle].first;
  }
  int past = 0, most = 0;
  for (const auto& [cycle, n] : per_cycle) {
    past += n.second - n.first;
    most = std::max(most, past);
  }
  EXPECT_EQ(most, 2);
  EXPECT_EQ(past, 0);
  EXPECT_GT(p.pe.counters.credit_stall, 0u);
}

TEST(PeEngine, RaysBeyondTheOnChipCapacitySpillAndComeBack) {
  MachineConfig c = fast(), roomy = fast();
  c.front_buffer_capacity = 1;
  EnginePe p("balls-1", 8, c), q("balls-1", 8, roomy);
  int spilled = 0;
  for (const std::string& line : p.run())
    spilled += parse(line).detail.find("spilled") != std::string::npos;
  q.run();
  EXPECT_GT(spilled, 0);
  EXPECT_EQ(uint64_t(spilled), p.pe.counters.spills);
  EXPECT_EQ(q.pe.counters.spills, 0u);
  EXPECT_TRUE(same(p.frame, q.frame));
  EXPECT_EQ(p.ids, q.ids);
}

/// The configurations of the tests above: back-to-back items (pipelined and not), a full FIFO
/// stalling shading, credits, spills; each runs to its finish, with the same unit statistics.
TEST(PeEngine, APlainCycleByCycleDriverWritesTheSameEventLogs) {
  std::vector<std::pair<std::string, MachineConfig>> cases;
  cases.emplace_back("fast", fast());
  for (int interval : {1, 0}) {
    MachineConfig c = fast();
    c.fb_dispatch_cycles = 3;
    c.dispatch_interval = interval;
    cases.emplace_back("dispatch_interval " + std::to_string(interval), c);
  }
  MachineConfig c = fast();
  c.feedback_fifo_depth = 1;
  cases.emplace_back("feedback_fifo_depth 1", c);
  c = fast();
  c.loop_credits = 2;
  cases.emplace_back("loop_credits 2", c);
  c = fast();
  c.front_buffer_capacity = 1;
  cases.emplace_back("front_buffer_capacity 1", c);
  for (const auto& [name, config] : cases) {
    EnginePe engine("balls-1", 8, config), driver("balls-1", 8, config);
    const std::vector<std::string> a = engine.run(), b = driver.run_cycle_driver();
    EXPECT_GT(a.size(), 1000u) << name;
    EXPECT_TRUE(a == b) << name << ": the event logs differ";
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
      if (a[i] != b[i]) {
        ADD_FAILURE() << name << ", line " << i + 1 << ": engine '" << a[i] << "', driver '" << b[i]
                      << "'";
        break;
      }
    EXPECT_TRUE(same(engine.frame, driver.frame)) << name;
    EXPECT_EQ(engine.pe.counters.finish, driver.pe.counters.finish) << name;
    EXPECT_GT(driver.pe.counters.finish, 0u) << name;
    for (const UnitSpec& u : unit_table()) {
      const UnitStats x = engine.pe.counters.total(u.kind), y = driver.pe.counters.total(u.kind);
      EXPECT_EQ(x.items, y.items) << name << " " << u.name;
      EXPECT_EQ(x.busy_cycles, y.busy_cycles) << name << " " << u.name;
      EXPECT_EQ(x.held_cycles, y.held_cycles) << name << " " << u.name;
      EXPECT_EQ(x.starved_cycles, y.starved_cycles) << name << " " << u.name;
    }
    EXPECT_EQ(engine.pe.counters.credit_stall, driver.pe.counters.credit_stall) << name;
    EXPECT_EQ(engine.pe.counters.spills, driver.pe.counters.spills) << name;
  }
}

}  // namespace
}  // namespace rtm
