// A pipelined unit's timing (units/pipeline.h, units/unit_step.h) on hand-built item sequences,
// without a scheduler: back-to-back items, gaps, variable latencies, a full output stalling the
// whole pipeline, and interval = latency holding one item at a time.
#include "units/pipeline.h"

#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "units/unit_step.h"
#include "units/wakeups.h"

namespace rtm {
namespace {

TEST(Pipeline, BackToBackItemsLeaveOneAfterAnotherAfterTheLatency) {
  Pipeline<int> p;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(p.can_accept(uint64_t(i)));
    EXPECT_EQ(p.accept(i, uint64_t(i), 5, 1), uint64_t(i + 5));
  }
  EXPECT_EQ(p.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(p.retire(uint64_t(i + 5)), i);
  EXPECT_TRUE(p.empty());
}

TEST(Pipeline, TheIntervalSpacesAcceptances) {
  Pipeline<int> p;
  p.accept(0, 0, 6, 3);
  EXPECT_FALSE(p.can_accept(2));
  EXPECT_TRUE(p.can_accept(3));
  EXPECT_EQ(p.ready(), 3u);
}

TEST(Pipeline, IntervalEqualToLatencyHoldsOneItem) {
  Pipeline<int> p;
  p.accept(0, 10, 4, 4);
  EXPECT_FALSE(p.can_accept(13));
  // At 14 the result is due: until it is written the unit is stalled, afterwards free.
  EXPECT_FALSE(p.can_accept(14));
  p.retire(14);
  EXPECT_TRUE(p.can_accept(14));
}

TEST(Pipeline, AShortItemBehindALongOneLeavesACycleAfterIt) {
  Pipeline<int> p(1);
  EXPECT_EQ(p.accept(0, 0, 4, 1), 4u);
  EXPECT_EQ(p.accept(1, 1, 2, 1), 5u);  // its own latency says 3: in order, one a cycle
  EXPECT_EQ(p.accept(2, 2, 9, 1), 11u);
}

TEST(Pipeline, AGapLeavesTheUnitIdleAndItsTimingUnchanged) {
  Pipeline<int> p;
  p.accept(0, 0, 3, 1);
  p.retire(3);
  EXPECT_TRUE(p.empty());
  EXPECT_EQ(p.accept(1, 20, 3, 1), 23u);
}

TEST(Pipeline, AStalledResultMovesEverythingBehindIt) {
  Pipeline<int> p;
  p.accept(0, 0, 4, 1);  // due 4
  p.accept(1, 1, 4, 1);  // due 5
  p.accept(2, 2, 4, 3);  // due 6, next acceptance at 5
  // The head's FIFO is full from 4 to 7: three cycles of stall.
  EXPECT_TRUE(p.stalled(4));
  EXPECT_FALSE(p.can_accept(5));
  EXPECT_EQ(p.retire(7), 0);
  EXPECT_EQ(p.head().due, 8u);
  EXPECT_EQ(p.ready(), 8u);
  EXPECT_EQ(p.retire(8), 1);
  EXPECT_EQ(p.head().due, 9u);
}

TEST(Pipeline, AStallAfterTheUnitCouldAcceptFreesItWhenTheResultIsWritten) {
  Pipeline<int> p;
  p.accept(0, 0, 4, 1);  // ready from 1, no further item arrives
  EXPECT_EQ(p.retire(9), 0);
  EXPECT_TRUE(p.can_accept(9));
}

/// A scheduler for step_unit in a test: items arrive at given times, the output FIFO refuses
/// writes in given cycles; records when each item is accepted and written.
struct Harness {
  std::vector<uint64_t> arrivals;  // item i arrives at arrivals[i]
  std::vector<uint64_t> latency;   // item i's latency
  uint64_t interval = 1;           // 0: the item's latency (unpipelined)
  std::vector<bool> full;          // full[t]: the output refuses writes at t

  Pipeline<int> pipe{1};
  Wakeups wakeups;
  size_t next = 0;
  bool waiting = false;
  std::map<int, uint64_t> accepted, written;

  bool write_head(uint64_t now) {
    if (now < full.size() && full[now]) return false;
    written[pipe.head().item] = now;
    return true;
  }
  void woke(uint64_t) { waiting = false; }
  void retired(int) {}
  bool accept(uint64_t now) {
    if (next == arrivals.size() || arrivals[next] > now) return false;
    const int i = int(next++);
    accepted[i] = now;
    pipe.accept(i, now, latency[size_t(i)], interval ? interval : latency[size_t(i)]);
    return true;
  }
  bool wait_for_input() { return waiting = true; }
  void want(uint64_t t) { wakeups.want(t, 0); }

  void run() {
    for (uint64_t now = 0; now < 1000; ++now) {
      const bool woken = wakeups.next().first == now ||
                         (waiting && next < arrivals.size() && arrivals[next] == now);
      if (!woken && now > 0) continue;
      wakeups.fired(now);
      step_unit(pipe, now, 1, nullptr, *this);
    }
  }
};

TEST(StepUnit, PipelinedBackToBackItems) {
  Harness h;
  h.arrivals = {0, 0, 0, 0};
  h.latency = {4, 4, 4, 4};
  h.run();
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(h.accepted[i], uint64_t(i));
    EXPECT_EQ(h.written[i], uint64_t(i + 4));
  }
}

TEST(StepUnit, UnpipelinedTakesTheNextItemWhenTheResultIsWritten) {
  Harness h;
  h.arrivals = {0, 0, 0};
  h.latency = {4, 2, 3};
  h.interval = 0;
  h.run();
  EXPECT_EQ(h.accepted[1], 4u);
  EXPECT_EQ(h.written[1], 6u);
  EXPECT_EQ(h.accepted[2], 6u);
  EXPECT_EQ(h.written[2], 9u);
}

TEST(StepUnit, AGapThenAnItemArrivingWhileOthersAreInside) {
  Harness h;
  h.arrivals = {0, 10, 11};
  h.latency = {3, 5, 1};
  h.run();
  EXPECT_EQ(h.written[0], 3u);
  EXPECT_EQ(h.accepted[1], 10u);
  EXPECT_EQ(h.accepted[2], 11u);
  EXPECT_EQ(h.written[1], 15u);
  EXPECT_EQ(h.written[2], 16u);  // in order, one cycle behind
}

TEST(StepUnit, AFullOutputStallsThePipeline) {
  Harness h;
  h.arrivals = {0, 1, 2, 3};
  h.latency = {4, 4, 4, 4};
  h.full.assign(20, false);
  h.full[4] = h.full[5] = true;  // item 0 waits two cycles for room
  h.run();
  EXPECT_EQ(h.written[0], 6u);
  EXPECT_EQ(h.written[1], 7u);
  EXPECT_EQ(h.written[2], 8u);
  // Item 3 was inside too (accepted at 3): it moves by the same two cycles.
  EXPECT_EQ(h.accepted[3], 3u);
  EXPECT_EQ(h.written[3], 9u);
}

TEST(StepUnit, NothingIsAcceptedDuringAStall) {
  Harness h;
  h.arrivals = {0, 4};
  h.latency = {4, 1};
  h.full.assign(20, false);
  h.full[4] = h.full[5] = h.full[6] = true;
  h.run();
  EXPECT_EQ(h.written[0], 7u);
  EXPECT_EQ(h.accepted[1], 7u);
  EXPECT_EQ(h.written[1], 8u);
}

TEST(Wakeups, ARepeatedTimeIsOneWakeUpKeepingItsFirstOrder) {
  Wakeups w;
  EXPECT_TRUE(w.want(10, 1));
  EXPECT_TRUE(w.want(5, 2));
  EXPECT_FALSE(w.want(10, 3));
  EXPECT_EQ(w.next(), std::make_pair(uint64_t(5), uint64_t(2)));
  w.fired(5);
  EXPECT_EQ(w.next(), std::make_pair(uint64_t(10), uint64_t(1)));
  w.fired(10);
  EXPECT_TRUE(w.empty());
}

}  // namespace
}  // namespace rtm
