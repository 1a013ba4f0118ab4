// The replicated units' dispatch order (units/lane_dispatcher.h): the lowest-numbered waiting unit
// takes each ray, whatever order the units began to wait in.
#include "units/lane_dispatcher.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace rtm {
namespace {

TEST(LaneDispatcher, TheLowestNumberedWaitingLaneTakesEachRay) {
  LaneDispatcher d(0);
  EXPECT_FALSE(d.any_idle());
  for (int lane : {200, 3, 64, 3}) d.idle(lane);  // a lane already waiting is counted once
  EXPECT_EQ(d.take(), 3);
  EXPECT_EQ(d.take(), 64);
  d.idle(0);
  EXPECT_EQ(d.take(), 0);
  EXPECT_EQ(d.take(), 200);
  EXPECT_FALSE(d.any_idle());
}

TEST(LaneDispatcher, ABusyLaneIsPassedOver) {
  LaneDispatcher d(3);
  d.busy(0);
  d.busy(0);
  EXPECT_EQ(d.take(), 1);
  EXPECT_EQ(d.take(), 2);
  EXPECT_FALSE(d.any_idle());
}

TEST(LaneDispatcher, HoldsUpToItsBoundAndRefusesMore) {
  LaneDispatcher full(LaneDispatcher::kMaxLanes);
  int last = -1;
  while (full.any_idle()) last = full.take();
  EXPECT_EQ(last, LaneDispatcher::kMaxLanes - 1);
  EXPECT_THROW(LaneDispatcher(LaneDispatcher::kMaxLanes + 1), std::invalid_argument);
  EXPECT_THROW(LaneDispatcher(-1), std::invalid_argument);
}

}  // namespace
}  // namespace rtm
