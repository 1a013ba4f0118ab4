// The unit table is what the counters, the statistics, the event log, the watchdog and both
// schedulers' lists of units are built from: its entries must agree with the unit kinds, the
// configuration keys and the FIFO table.
#include "units/unit_table.h"

#include <algorithm>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "units/pe_state.h"

namespace rtm {
namespace {

TEST(UnitTable, EachEntryIsItsKindInRankOrderAndNamedOnce) {
  std::set<std::string> names;
  for (size_t i = 0; i < kUnitKinds; ++i) {
    const UnitSpec& u = unit_table()[i];
    EXPECT_EQ(size_t(u.kind), i) << u.name;
    EXPECT_TRUE(names.insert(u.name).second) << u.name;
    EXPECT_NE(u.longest_item, nullptr) << u.name;
    EXPECT_TRUE(u.doc && *u.doc) << u.name;
    EXPECT_TRUE(u.label && *u.label) << u.name;
  }
}

TEST(UnitTable, ThePipelineOrderFollowsTheFifosAwayFromTheFrontBuffer) {
  const std::vector<UnitKind> order = pipeline_order();
  EXPECT_EQ(order, (std::vector<UnitKind>{UnitKind::FrontBuffer, UnitKind::Search, UnitKind::Mac,
                                          UnitKind::Root, UnitKind::Shading}));
  // Each kind comes after every kind that writes a FIFO it reads, but for the FIFOs back into
  // the front buffer.
  auto place = [&](UnitKind k) { return std::find(order.begin(), order.end(), k) - order.begin(); };
  for (const FifoSpec& f : fifo_table())
    for (UnitKind r : f.readers)
      for (UnitKind w : f.writers)
        if (r != UnitKind::FrontBuffer && r != w) {
          EXPECT_LT(place(w), place(r)) << f.name;
        }
}

TEST(UnitTable, CountKeysAreConfigurationKeysOfTheSameValue) {
  MachineConfig c;
  c.search_units = 3;
  c.intersection_units = 5;
  for (const UnitSpec& u : unit_table()) {
    if (!u.count) {
      EXPECT_EQ(u.count_key, nullptr) << u.name;
      EXPECT_EQ(unit_count(u.kind, c), 1) << u.name;
      continue;
    }
    const auto& keys = config_keys();
    const auto k = std::find_if(keys.begin(), keys.end(),
                                [&](const ConfigKey& k) { return k.name == u.count_key; });
    ASSERT_NE(k, keys.end()) << u.name << ": no key " << u.count_key;
    EXPECT_EQ(k->get(c), std::to_string(unit_count(u.kind, c))) << u.name;
  }
}

TEST(UnitTable, EveryUnitReadsAndWritesAFifoAndPerLaneFifosFollowTheirWriters) {
  MachineConfig c;
  c.intersection_units = 3;
  for (const UnitSpec& u : unit_table()) {
    EXPECT_FALSE(inputs(u.kind).empty()) << u.name;
    EXPECT_FALSE(outputs(u.kind).empty()) << u.name;
  }
  EXPECT_EQ(inputs(UnitKind::Root), std::vector<FifoId>{FifoId::Root});
  EXPECT_EQ(outputs(UnitKind::Mac), std::vector<FifoId>{FifoId::Root});
  for (const FifoSpec& f : fifo_table()) {
    EXPECT_EQ(fifo_count(f, c), f.per_lane ? 3 : 1) << f.name;
    // A FIFO per lane joins units of one number: its readers are as many as its writers.
    if (!f.per_lane) continue;
    for (UnitKind r : f.readers) {
      EXPECT_EQ(unit_count(r, c), unit_count(f.writers.front(), c)) << f.name;
    }
  }
}

TEST(UnitTable, CountersHoldOnePlacePerUnitAndSumThem) {
  MachineConfig c;
  c.search_units = 3;
  c.intersection_units = 2;
  PeCounters k;
  k.size_for(c);
  int n = 0;
  for (const UnitSpec& u : unit_table()) {
    ASSERT_EQ(k.units[size_t(u.kind)].size(), size_t(unit_count(u.kind, c))) << u.name;
    for (int i = 0; i < unit_count(u.kind, c); ++i) k.unit(u.kind, i).items = uint64_t(++n);
  }
  EXPECT_EQ(k.total(UnitKind::Search).items, 3u + 4u + 5u);
  EXPECT_EQ(k.all().items, uint64_t(n * (n + 1) / 2));
  EXPECT_THROW(k.unit(UnitKind::Mac, 2), std::out_of_range);
}

TEST(UnitTable, TheWatchdogBoundGrowsWithWhatEachUnitWaitsFor) {
  const MachineConfig c;
  ItemBounds small, big;
  small.walk_voxels = 4;  // the smallest grid's walk: one voxel, and 3
  big.fullest_voxel = 10;
  big.most_clips = 2;
  big.lights = 3;
  big.walk_voxels = 20;
  big.access = 7;
  for (const UnitSpec& u : unit_table()) {
    EXPECT_GT(u.longest_item(c, small), 0u) << u.name;
    EXPECT_GT(u.longest_item(c, big), u.longest_item(c, small)) << u.name;
  }
}

}  // namespace
}  // namespace rtm
