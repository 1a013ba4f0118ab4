#include "frame/frame_stats.h"

#include <gtest/gtest.h>

#include "frame/machine_result.h"

namespace rtm {
namespace {

UnitStats search_unit(uint64_t busy, uint64_t issue, uint64_t held, uint64_t starved) {
  UnitStats u;
  u.busy_cycles = busy;
  u.issue_cycles = issue;
  u.held_cycles = held;
  u.starved_cycles = starved;
  return u;
}

/// Two PEs with two MAC lanes each, clocked at 10 ns: the host pre-processes for 100 cycles and
/// transfers for 50, the PEs work from cycle 150 (PE 0 for 1000 cycles, PE 1 for 500), the
/// gather takes the last 50 of the frame's 1200 cycles.
struct TwoPes {
  MachineConfig config;
  MachineResult result;

  TwoPes() {
    config.pes = 2;
    config.clock_ns = 10;
    config.search_units = 4;
    config.intersection_units = 2;
    auto at = [](uint64_t cycle) { return cycle * 10000; };  // in ticks of 1 ps
    MachineResult& m = result;
    m.clock_ticks = at(1);
    m.cycles = 1200;
    m.mac_products = 2000;
    m.host.rays = at(100);
    m.host.work = at(100);
    m.host.transfer = at(150);
    m.host.pes_done = at(1150);
    m.host.gathered = at(1200);
    m.per_pe.resize(2);
    PeCounters& a = m.per_pe[0];
    a.size_for(config);
    a.start = at(150);
    a.finish = at(1150);
    a.credit_stall = at(90);
    a.unit(UnitKind::FrontBuffer, 0).busy_cycles = 300;
    // The four search units: busy 2000 cycles together, issue 600, held 6000, starved 1200.
    a.units[size_t(UnitKind::Search)] = {
        search_unit(800, 300, 2000, 0), search_unit(600, 150, 2000, 200),
        search_unit(400, 100, 1000, 400), search_unit(200, 50, 1000, 600)};
    a.unit(UnitKind::Mac, 0).busy_cycles = 1600;
    a.unit(UnitKind::Root, 0).busy_cycles = 400;
    a.unit(UnitKind::Shading, 0).busy_cycles = 240;
    PeCounters& b = m.per_pe[1];
    b.size_for(config);
    b.start = at(150);
    b.finish = at(650);
    b.credit_stall = at(60);
    b.unit(UnitKind::FrontBuffer, 0).busy_cycles = 150;
    b.units[size_t(UnitKind::Search)] = {search_unit(400, 0, 0, 0), search_unit(300, 0, 0, 0),
                                         search_unit(200, 0, 0, 0), search_unit(100, 0, 0, 0)};
    b.unit(UnitKind::Mac, 0).busy_cycles = 400;
    b.unit(UnitKind::Root, 0).busy_cycles = 200;
    b.unit(UnitKind::Shading, 0).busy_cycles = 60;
  }
};

TEST(FrameStats, UtilisationOverTheFramePerUnit) {
  const TwoPes t;
  const FrameUtilisation u = frame_stats(t.result, t.config).utilisation;
  // Busy cycles over the PEs' 2 x 1200 cycles; search over 4 units, MAC and root over 2 lanes.
  EXPECT_DOUBLE_EQ(u[UnitKind::FrontBuffer], 450.0 / 2400);
  EXPECT_DOUBLE_EQ(u[UnitKind::Search], 750.0 / 2400);
  EXPECT_DOUBLE_EQ(u[UnitKind::Mac], 1000.0 / 2400);
  EXPECT_DOUBLE_EQ(u[UnitKind::Root], 300.0 / 2400);
  EXPECT_DOUBLE_EQ(u[UnitKind::Shading], 300.0 / 2400);
}

TEST(FrameStats, ProfileOverTheWorkingWindows) {
  const TwoPes t;
  const FrameProfile f = frame_stats(t.result, t.config).profile;
  EXPECT_DOUBLE_EQ(f.total, 1200);
  EXPECT_DOUBLE_EQ(f.host_preprocess, 100);
  EXPECT_DOUBLE_EQ(f.transfer, 50);
  EXPECT_DOUBLE_EQ(f.pe, 1000);
  EXPECT_DOUBLE_EQ(f.gather, 50);
  // The working windows add up to 1500 cycles.
  EXPECT_DOUBLE_EQ(f.busy[UnitKind::FrontBuffer], 450.0 / 1500);
  EXPECT_DOUBLE_EQ(f.busy[UnitKind::Search], 750.0 / 1500);
  EXPECT_DOUBLE_EQ(f.busy[UnitKind::Mac], 1000.0 / 1500);
  EXPECT_DOUBLE_EQ(f.busy[UnitKind::Root], 300.0 / 1500);
  EXPECT_DOUBLE_EQ(f.busy[UnitKind::Shading], 300.0 / 1500);
  // A pipelined unit: its entry, the items inside it and its starvation, per search unit.
  EXPECT_DOUBLE_EQ(f.issue[UnitKind::Search], 150.0 / 1500);
  EXPECT_DOUBLE_EQ(f.occupancy[UnitKind::Search], 1500.0 / 1500);
  EXPECT_DOUBLE_EQ(f.starved[UnitKind::Search], 300.0 / 1500);
  EXPECT_DOUBLE_EQ(f.credit_stall, 150.0 / 1500);
  EXPECT_DOUBLE_EQ(f.imbalance, 1000.0 / 750);
}

// Streamed rays: the host's last ray is made late, but it worked only 60 of the 150 cycles before
// the transfer was done; the rest it waited for the link.
TEST(FrameStats, StreamedRaysSplitTheHostsWorkFromItsWaitForTheLink) {
  TwoPes t;
  t.result.host.rays = 140 * t.result.clock_ticks;
  t.result.host.work = 60 * t.result.clock_ticks;
  const FrameProfile f = frame_stats(t.result, t.config).profile;
  EXPECT_DOUBLE_EQ(f.host_preprocess, 60);
  EXPECT_DOUBLE_EQ(f.transfer, 90);
  EXPECT_DOUBLE_EQ(f.host_preprocess + f.transfer + f.pe + f.gather, f.total);
}

// The busiest port, over the frame: it carries the host's writes outside the working windows too.
TEST(FrameStats, TheBusiestMemoryPortOverTheFrame) {
  TwoPes t;
  t.result.memory_use.resize(2);
  t.result.memory_use[0].port_busy_cycles = {300, 600};
  t.result.memory_use[1].port_busy_cycles = {900};
  EXPECT_DOUBLE_EQ(frame_stats(t.result, t.config).profile.memory_port, 900.0 / 1200);
}

TEST(FrameStats, EachSearchUnitOverItsPesWorkingWindow) {
  const TwoPes t;
  const FrameStats s = frame_stats(t.result, t.config);
  ASSERT_EQ(s.search_units.size(), 2u);
  ASSERT_EQ(s.search_units[0].size(), 4u);
  // PE 0 works 1000 cycles, PE 1 500.
  const double busy[] = {0.8, 0.6, 0.4, 0.2}, issue0[] = {0.3, 0.15, 0.1, 0.05};
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(s.search_units[0][k].busy, busy[k]) << k;
    EXPECT_DOUBLE_EQ(s.search_units[0][k].issue, issue0[k]) << k;
    EXPECT_DOUBLE_EQ(s.search_units[1][k].busy, busy[k]) << k;
    EXPECT_DOUBLE_EQ(s.search_units[1][k].issue, 0) << k;
  }
}

TEST(FrameStats, APeThatNeverWorkedHasNoSearchUnitShares) {
  TwoPes t;
  t.result.per_pe[1].start = t.result.per_pe[1].finish = 0;  // no pixels
  const FrameStats s = frame_stats(t.result, t.config);
  for (const SearchUnitShares& u : s.search_units[1]) {
    EXPECT_DOUBLE_EQ(u.busy, 0);
    EXPECT_DOUBLE_EQ(u.issue, 0);
  }
}

TEST(FrameStats, TheBottleneckOfTheProfile) {
  TwoPes t;
  t.result.per_pe[0].unit(UnitKind::Mac, 0).issue_cycles = 1600;
  t.result.per_pe[1].unit(UnitKind::Mac, 0).issue_cycles = 400;
  FrameStats s = frame_stats(t.result, t.config);
  EXPECT_EQ(s.bottleneck.name, "mac")
      << "the MAC lanes' entries are taken 2/3 of the working windows";
  EXPECT_EQ(s.bottleneck.reason, bottleneck(s.profile).reason);
  t.result.per_pe[0].unit(UnitKind::Mac, 0).issue_cycles = 600;
  t.result.per_pe[1].unit(UnitKind::Mac, 0).issue_cycles = 200;
  s = frame_stats(t.result, t.config);
  EXPECT_EQ(s.bottleneck.name, "load_imbalance") << "nothing saturated, PE 0 works 1.33 x the mean";
}

TEST(FrameStats, MacBound) {
  TwoPes t;
  FrameStats s = frame_stats(t.result, t.config);
  EXPECT_DOUBLE_EQ(s.mac_bound_cycles, 1000);
  EXPECT_DOUBLE_EQ(s.cycles_over_mac_bound, 1.2);
  t.result.mac_products = 2001;
  s = frame_stats(t.result, t.config);
  EXPECT_DOUBLE_EQ(s.mac_bound_cycles, 1001) << "rounded up: a PE can't do half a product";
  t.result.mac_products = 0;
  s = frame_stats(t.result, t.config);
  EXPECT_DOUBLE_EQ(s.mac_bound_cycles, 0);
  EXPECT_DOUBLE_EQ(s.cycles_over_mac_bound, 0) << "no MAC products: no bound to be over";
}

TEST(FrameStats, AnEmptyRunHasNoUtilisationAndNoImbalance) {
  const MachineConfig c;
  MachineResult m;
  m.clock_ticks = 10000;
  const FrameStats s = frame_stats(m, c);
  EXPECT_DOUBLE_EQ(s.utilisation[UnitKind::Mac], 0);
  EXPECT_DOUBLE_EQ(s.profile.busy[UnitKind::Mac], 0);
  EXPECT_DOUBLE_EQ(s.profile.imbalance, 1);
  EXPECT_EQ(s.bottleneck.name, "latency");
}

}  // namespace
}  // namespace rtm
