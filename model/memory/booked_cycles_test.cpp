// BookedCycles against a std::set of the same cycles, on random bookings, queries and forgetting
// across word boundaries.
#include "memory/booked_cycles.h"

#include <random>
#include <set>

#include <gtest/gtest.h>

namespace rtm {
namespace {

TEST(BookedCycles, AnswersAsASetOfTheSameCyclesWould) {
  std::mt19937_64 rng(11);
  BookedCycles b;
  std::set<uint64_t> s;
  uint64_t floor = 1000;  // nothing before it is asked about or booked
  for (int i = 0; i < 20000; ++i) {
    const uint64_t c = floor + rng() % 300;
    switch (rng() % 8) {
      case 0:
      case 1:
      case 2:
        b.book(c);
        s.insert(c);
        break;
      case 3:
        floor += rng() % 40;
        b.forget_before(floor);
        s.erase(s.begin(), s.lower_bound(floor));
        break;
      default: {
        ASSERT_EQ(b.booked(c), s.count(c) == 1) << c;
        const auto next = s.lower_bound(c);
        ASSERT_EQ(b.next_booked(c), next == s.end() ? BookedCycles::kNone : *next) << c;
        uint64_t free = c;
        while (s.count(free)) ++free;
        ASSERT_EQ(b.next_free(c), free) << c;
      }
    }
  }
}

TEST(BookedCycles, EmptyEverythingIsFree) {
  BookedCycles b;
  EXPECT_FALSE(b.booked(5));
  EXPECT_EQ(b.next_booked(5), BookedCycles::kNone);
  EXPECT_EQ(b.next_free(5), 5u);
  b.book(127);
  b.book(128);
  EXPECT_EQ(b.next_free(127), 129u);
  EXPECT_EQ(b.next_booked(0), 127u);
  b.forget_before(128);
  EXPECT_FALSE(b.booked(127));
  EXPECT_EQ(b.next_booked(0), 128u);
  // A later request may book before the earliest booked cycle.
  b.book(70);
  EXPECT_TRUE(b.booked(70));
  EXPECT_EQ(b.next_booked(0), 70u);
  EXPECT_EQ(b.next_free(70), 71u);
}

TEST(BookedCycles, BookingASpanBooksEachOfItsCycles) {
  std::mt19937_64 rng(3);
  for (int run = 0; run < 200; ++run) {
    BookedCycles spans, singles;
    for (int i = 0; i < 20; ++i) {
      const uint64_t from = 500 + rng() % 400, n = rng() % 150;
      spans.book(from, n);
      for (uint64_t c = from; c < from + n; ++c) singles.book(c);
    }
    for (uint64_t c = 400; c < 1100; ++c) {
      ASSERT_EQ(spans.booked(c), singles.booked(c)) << c;
      ASSERT_EQ(spans.next_free(c), singles.next_free(c)) << c;
      ASSERT_EQ(spans.next_booked(c), singles.next_booked(c)) << c;
    }
  }
}

}  // namespace
}  // namespace rtm
