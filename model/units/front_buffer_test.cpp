// The front buffer's policy on hand-built sequences, without any scheduler: never more rays past
// it than credits allow, waiting rays before new primary rays in arrival order, spills beyond the
// on-chip capacity and their refill order, stall accounting, and when the PE is done.
#include "units/front_buffer.h"

#include <random>

#include <gtest/gtest.h>

namespace rtm {
namespace {

using Policy = FrontBufferPolicy<int>;
using Next = Policy::Next;

PeState pe_with(int credits, int capacity) {
  PeState pe;
  pe.config.loop_credits = credits;
  pe.config.front_buffer_capacity = capacity;
  pe.config.fb_dispatch_cycles = 1;
  return pe;
}

/// Hands out whatever the policy says next; returns the ray (queued) or -1 - primary number.
int hand_out(Policy& p, uint64_t now = 0) {
  uint64_t cycles = 0;
  if (p.next() == Next::Queued) {
    bool spilled = false;
    MemoryWait wait;
    const int r = p.pop_queued(now, cycles, spilled, wait);
    p.dispatched(now, uint32_t(r), cycles, spilled ? kFromSpill : kFromQueue);
    return r;
  }
  EXPECT_EQ(p.next(), Next::Primary);
  MemoryWait wait;
  const int i = int(p.pop_primary(now, cycles, wait));
  p.dispatched(now, uint32_t(1000 + i), cycles, kFromHost);
  return -1 - i;
}

TEST(FrontBufferPolicy, NeverMoreRaysPastItThanCredits) {
  PeState pe = pe_with(3, 64);
  Policy p(pe, 10);
  p.primaries_arrived(10);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(hand_out(p), -1 - i);
  EXPECT_EQ(p.in_flight(), 3);
  EXPECT_EQ(p.next(), Next::Wait) << "all credits taken";
  p.ended();
  EXPECT_EQ(p.next(), Next::Primary) << "an end returns a credit";
  hand_out(p);
  p.spawned(7);  // a spawned ray takes no credit back...
  EXPECT_EQ(p.next(), Next::Wait) << "...and waits for one";
  p.returned(42);  // a ray fed back returns its credit
  EXPECT_EQ(p.next(), Next::Queued);
}

TEST(FrontBufferPolicy, WaitingRaysGoFirstInArrivalOrder) {
  PeState pe = pe_with(4, 64);
  Policy p(pe, 3);
  p.primaries_arrived(3);
  EXPECT_EQ(hand_out(p), -1);
  EXPECT_EQ(hand_out(p), -2);
  p.returned(5);
  p.spawned(9);
  p.returned(6);
  EXPECT_EQ(hand_out(p), 5);
  EXPECT_EQ(hand_out(p), 9);
  EXPECT_EQ(hand_out(p), 6);
  EXPECT_EQ(hand_out(p), -3) << "the last primary ray only once none waits";
}

TEST(FrontBufferPolicy, RaysBeyondTheCapacitySpillAndComeBackInArrivalOrder) {
  PeState pe = pe_with(8, 2);
  Policy p(pe, 0);
  for (int r = 1; r <= 4; ++r) p.spawned(r);  // four waiting, two places on chip
  // A ray comes from the spill area while more rays wait than the chip holds: 4 and 3 waiting.
  const bool want_spilled[] = {true, true, false, false};
  for (int r = 1; r <= 4; ++r) {
    ASSERT_EQ(p.next(), Next::Queued);
    uint64_t cycles = 0;
    bool spilled = false;
    MemoryWait wait;
    EXPECT_EQ(p.pop_queued(0, cycles, spilled, wait), r) << "in arrival order";
    EXPECT_EQ(spilled, want_spilled[r - 1]) << "ray " << r;
    // Without a local memory (none here) the move costs nothing; with one, its read's time
    // (Cli.SpillsCostTheirRecordsTransfer).
    EXPECT_EQ(cycles, 1u) << "the dispatch";
    p.dispatched(0, uint32_t(r), cycles, spilled ? kFromSpill : kFromQueue);
  }
  EXPECT_EQ(pe.counters.spills, 2u);
  // Unpipelined (dispatch_interval 0), the next ray goes when this one's dispatch is over.
  pe.config.dispatch_interval = 0;
  EXPECT_EQ(p.interval(9), 9u);
  pe.config.dispatch_interval = 1;
  EXPECT_EQ(p.interval(9), 1u) << "pipelined: the next ray while this one comes from local memory";
}

TEST(FrontBufferPolicy, CreditStallsCountOnlyWhileRaysWaitForACredit) {
  PeState pe = pe_with(1, 64);
  Policy p(pe, 2);
  p.primaries_arrived(2);
  hand_out(p);
  p.wait(100);  // a primary ray is there, no credit
  p.woke(130);
  EXPECT_EQ(pe.counters.credit_stall, 30u);
  p.ended();
  hand_out(p);
  p.ended();
  p.wait(200);  // nothing waiting: not a stall
  p.woke(260);
  EXPECT_EQ(pe.counters.credit_stall, 30u);
}

TEST(FrontBufferPolicy, FinishedOnlyWhenEveryRayHasArrivedAndEnded) {
  PeState pe = pe_with(2, 64);
  Policy p(pe, 2);
  p.primaries_arrived(1);
  hand_out(p);
  p.ended();
  EXPECT_EQ(p.next(), Next::Wait) << "a primary ray has not arrived yet";
  p.primaries_arrived(2);
  hand_out(p);
  p.returned(3);
  EXPECT_EQ(p.next(), Next::Queued);
  hand_out(p);
  EXPECT_EQ(p.next(), Next::Wait) << "a ray is still past the front buffer";
  p.ended();
  EXPECT_EQ(p.next(), Next::Finished);
  p.finish(500);
  EXPECT_TRUE(p.finished());
  EXPECT_EQ(pe.counters.finish, 500u);
}

// Random arrivals against a model of the credit rule: in flight never exceeds the credits, every
// ray handed out once per arrival, and the PE finishes exactly when everything has ended.
TEST(FrontBufferPolicy, RandomTrafficKeepsTheCreditRule) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int credits = 1 + int(rng() % 5), primaries = 1 + int(rng() % 20);
    PeState pe = pe_with(credits, 1 + int(rng() % 4));
    Policy p(pe, size_t(primaries));
    std::vector<int> past;  // rays past the front buffer
    int next_id = 0, handed = 0, arrived = 0;
    for (int steps = 0; steps < 10000 && p.next() != Next::Finished; ++steps) {
      if (arrived < primaries && rng() % 3 == 0) p.primaries_arrived(size_t(++arrived));
      const Next n = p.next();
      if ((n == Next::Queued || n == Next::Primary) && rng() % 2) {
        const int r = hand_out(p);
        past.push_back(r < 0 ? next_id++ : r);
        ++handed;
        ASSERT_LE(p.in_flight(), credits);
        ASSERT_EQ(p.in_flight(), int(past.size()));
        continue;
      }
      if (past.empty()) continue;
      const size_t i = rng() % past.size();
      const int r = past[i];
      past.erase(past.begin() + long(i));
      switch (rng() % 4) {
        case 0:
          p.returned(r);
          break;  // walks on
        case 1:   // ends, spawning a child
          p.ended();
          if (rng() % 2) p.spawned(next_id++);
          break;
        default:
          p.ended();
      }
    }
    EXPECT_EQ(p.next(), Next::Finished) << "trial " << trial;
    EXPECT_EQ(p.in_flight(), 0);
    EXPECT_EQ(p.waiting(), 0u);
    EXPECT_GT(handed, 0);
  }
}

// A bounded spill area: new primary rays wait until every ray in the loop, and the new one, could
// each spawn its most children into what the front buffer holds; rays in the loop always go on.
TEST(FrontBufferPolicy, ABoundedSpillAreaHoldsBackPrimaryRaysNotRaysInTheLoop) {
  PeState pe = pe_with(8, 2);
  pe.spill_rays = 4;    // holds 2 + 4 = 6 rays
  pe.spawn_fanout = 2;  // each ray's end may spawn two
  Policy p(pe, 10);
  p.primaries_arrived(10);
  EXPECT_EQ(p.capacity(), 6u);
  // 1, 2, 3 rays in flight need 2, 4, 6 places; a fourth would need 8.
  for (int i = 0; i < 3; ++i) EXPECT_EQ(hand_out(p), -1 - i);
  EXPECT_EQ(p.next(), Next::Wait) << "credits are left, but no room for a fourth ray's children";
  p.ended();
  p.spawned(100);
  p.spawned(101);  // 2 waiting, 2 in flight: 2 + 3 * 2 > 6
  EXPECT_EQ(p.next(), Next::Queued) << "spawned rays are in the loop: they go";
  EXPECT_EQ(hand_out(p), 100);
  EXPECT_EQ(hand_out(p), 101);
  EXPECT_EQ(p.in_flight(), 4);
  p.ended();
  p.ended();
  p.ended();  // 1 in flight, none waiting: 0 + 2 * 2 <= 6
  EXPECT_EQ(p.next(), Next::Primary);
}

TEST(FrontBufferPolicy, RaysOutgrowingTheSpillAreaStopTheFrontBuffer) {
  PeState pe = pe_with(8, 1);
  pe.spill_rays = 1;
  pe.spawn_fanout = 3;
  FrontBufferPolicy<int> p(pe, 1);
  using D = FrontBufferPolicy<int>::Decision;
  p.primaries_arrived(1);
  bool ended = false;
  const auto drain = [&] {
    if (!ended) return;
    p.ended();
    for (int i = 0; i < 3; ++i) p.spawned(i);  // three children, room for two
    ended = false;
  };
  const D first = p.decide(0, 1, drain);
  ASSERT_EQ(first.kind, D::Primary);
  p.dispatched(0, 0, first.cycles, first.from);
  ended = true;
  EXPECT_EQ(p.decide(5, 1, drain).kind, D::None);
  EXPECT_TRUE(p.overflowed());
  EXPECT_EQ(pe.counters.spill_overflow, 3u);
  EXPECT_EQ(pe.counters.spill_overflow_at, 5u);
  EXPECT_FALSE(p.finished());
  EXPECT_EQ(p.decide(6, 1, drain).kind, D::None) << "it hands out nothing more";
}

TEST(FrontBufferPolicy, DecidesToAlignPrimaryRaysToTheClockAndToWaitForInput) {
  PeState pe = pe_with(8, 4);
  FrontBufferPolicy<int> p(pe, 1);
  using D = FrontBufferPolicy<int>::Decision;
  int drained = 0;
  const auto drain = [&] { ++drained; };
  // Nothing there yet: no decision, and the front buffer waits for input.
  EXPECT_EQ(p.decide(5, 10, drain).kind, D::None);
  EXPECT_TRUE(p.wait(5));
  EXPECT_TRUE(p.waiting_for_input());
  p.woke(7);
  EXPECT_FALSE(p.waiting_for_input());
  // A primary ray arrives between clock edges: it goes at the next edge, not before.
  p.primaries_arrived(1);
  const D align = p.decide(7, 10, drain);
  ASSERT_EQ(align.kind, D::Align);
  EXPECT_EQ(align.at, 10u);
  EXPECT_FALSE(p.wait(7)) << "aligning is not waiting for input";
  EXPECT_EQ(p.decide(8, 10, drain).kind, D::None) << "woken off the edge: still aligning";
  const D primary = p.decide(10, 10, drain);
  ASSERT_EQ(primary.kind, D::Primary);
  EXPECT_EQ(primary.primary, 0u);
  EXPECT_EQ(primary.from, kFromHost);
  EXPECT_EQ(drained, 2) << "inputs drained only when deciding, not while aligning";
  p.dispatched(10, 0, primary.cycles, primary.from);
  p.ended();
  EXPECT_EQ(p.decide(20, 10, drain).kind, D::None);
  EXPECT_TRUE(p.finished());
  EXPECT_FALSE(p.wait(20)) << "a finished front buffer waits for nothing";
}

}  // namespace
}  // namespace rtm

namespace rtm {
namespace {

/// A scheduler's operations for carry_out that record what the front buffer does.
struct Recorder {
  explicit Recorder(Policy& policy) : p(policy) {}
  Policy& p;
  int ends = 0;  ///< rays' ends waiting on its input
  std::vector<int> dispatched;
  int asks = 0, finishes = 0, frame_ends = 0;
  std::vector<uint64_t> wants;
  bool read_end() { return ends > 0 && ends--; }
  bool read(FifoId, int&) { return false; }
  void drained() {}
  int primary(size_t n) { return int(n); }
  void dispatch(int r, uint64_t cycles, uint8_t from, MemoryWait&&) {
    p.dispatched(0, uint32_t(r), cycles, from);
    dispatched.push_back(r);
  }
  void want(uint64_t t) { wants.push_back(t); }
  void finished() { ++finishes; }
  void ask_for_tile() { ++asks; }
  void frame_ended() { ++frame_ends; }
};

// partition = dynamic: the PE asks for a tile when it takes the last primary ray it holds, once
// until the host answers; its loop standing empty meanwhile is tile_wait; after the host's "none"
// it asks no more and finishes when its rays are done.
TEST(FrontBufferPolicy, ADynamicPartitionAsksWhenItTakesItsLastRay) {
  PeState pe = pe_with(4, 64);
  Policy p(pe, kRaysUnknown);
  Recorder ops(p);
  p.primaries_arrived(2, kRaysUnknown);  // the first tile, unasked
  EXPECT_TRUE(p.carry_out(0, 1, ops));
  EXPECT_EQ(ops.asks, 0) << "a ray left";
  EXPECT_TRUE(p.carry_out(1, 1, ops));
  EXPECT_EQ(ops.asks, 1) << "the last ray it held";
  EXPECT_FALSE(p.carry_out(2, 1, ops));
  ops.ends = 2;  // both rays end: the loop is empty, waiting for the answer
  EXPECT_FALSE(p.carry_out(3, 1, ops));
  EXPECT_FALSE(p.finished()) << "more may come";
  EXPECT_EQ(ops.asks, 1) << "one request out at a time";
  p.primaries_arrived(4, kRaysUnknown);  // the answer: a tile of two, at cycle 10
  EXPECT_TRUE(p.carry_out(10, 1, ops));
  EXPECT_EQ(pe.counters.tile_wait, 7u) << "empty from 3 to 10";
  EXPECT_EQ(ops.asks, 1);
  EXPECT_TRUE(p.carry_out(11, 1, ops));
  EXPECT_EQ(ops.asks, 2);
  p.primaries_arrived(4, 4);  // "none left"
  ops.ends = 2;
  EXPECT_FALSE(p.carry_out(12, 1, ops));
  EXPECT_TRUE(p.finished());
  EXPECT_EQ(ops.finishes, 1);
  EXPECT_EQ(ops.asks, 2);
  EXPECT_EQ(ops.dispatched, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(pe.counters.tile_wait, 7u) << "rays in the loop: no wait";
}

// A static partition never asks.
TEST(FrontBufferPolicy, AStaticPartitionNeverAsks) {
  PeState pe = pe_with(4, 64);
  Policy p(pe, 2);
  Recorder ops(p);
  p.primaries_arrived(2);
  EXPECT_TRUE(p.carry_out(0, 1, ops));
  EXPECT_TRUE(p.carry_out(1, 1, ops));
  ops.ends = 2;
  EXPECT_FALSE(p.carry_out(2, 1, ops));
  EXPECT_TRUE(p.finished());
  EXPECT_EQ(ops.asks, 0);
}

// frames > 1: a frame's first primary ray waits until the frame before has ended (its rays all
// out of the loop), and then for the PE's switch; the end is told once, the last frame's is the
// finish; the loop standing empty between frames is frame_wait.
TEST(FrontBufferPolicy, AFrameStartsOnceTheOneBeforeHasEndedAndThePeHasSwitched) {
  PeState pe = pe_with(4, 64);
  pe.frame_rays = 2;
  pe.frame_switch = 5;
  Policy p(pe, 4);
  Recorder ops(p);
  p.primaries_arrived(4);  // both frames' rays are in
  EXPECT_TRUE(p.carry_out(0, 1, ops));
  EXPECT_TRUE(p.carry_out(1, 1, ops));
  EXPECT_FALSE(p.carry_out(2, 1, ops)) << "frame 1's first ray waits for frame 0's end";
  ops.ends = 1;
  EXPECT_FALSE(p.carry_out(3, 1, ops)) << "a ray of frame 0 still in the loop";
  EXPECT_EQ(ops.frame_ends, 0);
  ops.ends = 1;
  EXPECT_FALSE(p.carry_out(4, 1, ops)) << "frame 0 ended at 4: the switch takes to 9";
  EXPECT_EQ(ops.frame_ends, 1);
  EXPECT_EQ(pe.counters.frame_ends, (std::vector<uint64_t>{4}));
  EXPECT_EQ(ops.wants.back(), 9u);
  EXPECT_FALSE(p.carry_out(7, 1, ops)) << "woken early: still switching";
  EXPECT_TRUE(p.carry_out(9, 1, ops));
  EXPECT_EQ(pe.counters.frame_wait, 5u);
  EXPECT_TRUE(p.carry_out(10, 1, ops));
  ops.ends = 2;
  EXPECT_FALSE(p.carry_out(11, 1, ops));
  EXPECT_TRUE(p.finished());
  EXPECT_EQ(ops.frame_ends, 1) << "the last frame's end is the finish";
  EXPECT_EQ(ops.finishes, 1);
  EXPECT_EQ(pe.counters.frame_ends, (std::vector<uint64_t>{4, 11}));
  EXPECT_EQ(ops.dispatched, (std::vector<int>{0, 1, 2, 3}));
}

}  // namespace
}  // namespace rtm
