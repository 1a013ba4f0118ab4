// The FIFO table is what both schedulers, the statistics and the waveforms are built from: its
// entries must agree with the configuration keys and with the units' outputs.
#include "units/fifo_table.h"

#include <algorithm>

#include <gtest/gtest.h>

namespace rtm {
namespace {

bool has(const std::vector<UnitKind>& v, UnitKind k) {
  return std::find(v.begin(), v.end(), k) != v.end();
}

TEST(FifoTable, EachEntryIsItsIdAndNamedOneWay) {
  for (size_t i = 0; i < kFifoCount; ++i) {
    const FifoSpec& f = fifo_table()[i];
    EXPECT_EQ(size_t(f.id), i) << f.name;
    const std::string name = f.name;
    EXPECT_EQ(name.substr(name.size() - 5), "_fifo") << name;
    EXPECT_FALSE(f.writers.empty()) << name;
    EXPECT_FALSE(f.readers.empty()) << name;
  }
}

TEST(FifoTable, DepthKeysAreConfigurationKeysOfTheSameValue) {
  MachineConfig c;
  int n = 0;
  for (const FifoSpec& f : fifo_table())
    c.*f.depth = 100 + n++;  // distinct values, so a wrong member shows
  for (const FifoSpec& f : fifo_table()) {
    const auto& keys = config_keys();
    const auto k = std::find_if(keys.begin(), keys.end(),
                                [&](const ConfigKey& k) { return k.name == f.depth_key; });
    ASSERT_NE(k, keys.end()) << f.name << ": no key " << f.depth_key;
    EXPECT_EQ(k->get(c), std::to_string(c.*f.depth)) << f.name;
  }
}

TEST(FifoTable, OnlyTheFrontBufferTakesCreditsBackAndOnlyTheRootFifoIsPerLane) {
  for (const FifoSpec& f : fifo_table()) {
    if (f.returns_credit) {
      EXPECT_TRUE(has(f.readers, UnitKind::FrontBuffer)) << f.name;
    }
    EXPECT_EQ(f.per_lane, f.id == FifoId::Root) << f.name;
    EXPECT_EQ(f.payload == Payload::MacResult, f.id == FifoId::Root) << f.name;
    EXPECT_EQ(f.payload == Payload::End, f.id == FifoId::Ends) << f.name;
  }
  // What a ray's end and a fed-back ray return, a spawned ray does not: it is new.
  EXPECT_TRUE(fifo_spec(FifoId::Ends).returns_credit);
  EXPECT_TRUE(fifo_spec(FifoId::FeedbackSearch).returns_credit);
  EXPECT_FALSE(fifo_spec(FifoId::Spawn).returns_credit);
  EXPECT_TRUE(fifo_spec(FifoId::Spawn).spawn_path);
}

}  // namespace
}  // namespace rtm
