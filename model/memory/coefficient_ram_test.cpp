// The MAC's coefficient RAM on hand-built sequences of primitives.
#include "memory/coefficient_ram.h"

#include <string>

#include <gtest/gtest.h>

namespace rtm {
namespace {

/// The accesses of `seq` (one primitive a letter): "h" for a hit, "m" for a miss.
std::string run(CoefficientRam& ram, const std::string& seq) {
  std::string out;
  for (char ch : seq) out += ram.access(uint32_t(ch - 'a')) ? 'h' : 'm';
  return out;
}

TEST(CoefficientRam, CapacityZeroHoldsEveryPrimitiveFromTheStart) {
  CoefficientRam ram;
  EXPECT_EQ(run(ram, "abcabcz"), "hhhhhhh");
  EXPECT_EQ(ram.misses(), 0u);
  EXPECT_EQ(ram.hit_rate(), 1.0);
  EXPECT_TRUE(ram.resident(12345));
}

TEST(CoefficientRam, LruEvictsTheLeastRecentlyUsed) {
  CoefficientRam ram(2);
  // a, b loaded; a used again, so c evicts b; b then evicts a (c was used after it).
  EXPECT_EQ(run(ram, "abacb"), "mmhmm");
  EXPECT_TRUE(ram.resident(uint32_t('c' - 'a')));
  EXPECT_TRUE(ram.resident(uint32_t('b' - 'a')));
  EXPECT_FALSE(ram.resident(uint32_t('a' - 'a')));
  EXPECT_EQ(ram.hits(), 1u);
  EXPECT_EQ(ram.misses(), 4u);
  EXPECT_EQ(ram.evictions(), 2u);
  EXPECT_DOUBLE_EQ(ram.hit_rate(), 0.2);
}

TEST(CoefficientRam, FifoEvictsTheOldestLoadedWhateverItsUse) {
  CoefficientRam ram(2, Replacement::Fifo);
  // The same sequence: c evicts a (loaded first, though just used); b is still there.
  EXPECT_EQ(run(ram, "abacb"), "mmhmh");
  EXPECT_EQ(run(ram, "a"), "m") << "a was evicted by c";
}

TEST(CoefficientRam, CapacityOneHitsOnlyARepeat) {
  CoefficientRam ram(1);
  EXPECT_EQ(run(ram, "aabbaba"), "mhmhmmm");
  EXPECT_EQ(ram.evictions(), 4u);
}

TEST(CoefficientRam, ACycleOverOneMoreThanTheCapacityMissesEveryTimeUnderLru) {
  CoefficientRam ram(3);
  EXPECT_EQ(run(ram, "abcdabcdabcd"), "mmmmmmmmmmmm");
}

TEST(CoefficientRam, EnoughCapacityMissesOnlyOncePerPrimitive) {
  for (uint32_t capacity : {4u, 5u, 100u}) {
    for (auto r : {Replacement::Lru, Replacement::Fifo}) {
      CoefficientRam ram(capacity, r);
      run(ram, "abcdabcddcbaaaddbc");
      EXPECT_EQ(ram.misses(), 4u) << capacity << ": the compulsory misses of four primitives";
      EXPECT_EQ(ram.hits(), 14u);
      EXPECT_EQ(ram.evictions(), 0u);
    }
  }
}

}  // namespace
}  // namespace rtm
