#include "machine/bottleneck.h"

#include <gtest/gtest.h>

namespace rtm {
namespace {

FrameProfile busy_pes() {
  FrameProfile p;
  p.total = 1000;
  p.host_preprocess = 50;
  p.transfer = 20;
  p.gather = 10;
  p.issue.mac = 0.3;
  p.issue.search = 0.2;
  return p;
}

TEST(Bottleneck, HostOrLinkTakingHalfTheFrame) {
  FrameProfile both = busy_pes();
  both.host_preprocess = 300;
  both.transfer = 250;
  EXPECT_EQ(bottleneck(both), "host_preprocessing");
  FrameProfile p = busy_pes();
  p.host_preprocess = 600;
  EXPECT_EQ(bottleneck(p), "host_preprocessing");
  p = busy_pes();
  p.transfer = 300;
  p.gather = 250;
  EXPECT_EQ(bottleneck(p), "interconnect");
}

TEST(Bottleneck, TheBusiestUnitWhenItIsSaturated) {
  FrameProfile p = busy_pes();
  p.issue.mac = 0.92;
  EXPECT_EQ(bottleneck(p), "mac");
  p.issue.mac = 0.5;
  p.issue.search = 0.7;
  EXPECT_EQ(bottleneck(p), "search");
  p.issue.search = 0.1;
  p.issue.shading = 0.65;
  EXPECT_EQ(bottleneck(p), "shading");
}

TEST(Bottleneck, APipelinedUnitHoldingItemsAllTheTimeIsNotSaturated) {
  FrameProfile p = busy_pes();
  p.busy.root = 0.98;  // a long latency, items inside nearly always ...
  p.issue.root = 0.2;  // ... but its entry mostly free
  p.issue.mac = 0.7;
  EXPECT_EQ(bottleneck(p), "mac");
}

TEST(Bottleneck, BackPressureImbalanceAndLatency) {
  FrameProfile p = busy_pes();
  p.credit_stall = 0.5;
  EXPECT_EQ(bottleneck(p), "loop_credits");
  p.credit_stall = 0;
  p.imbalance = 1.8;
  EXPECT_EQ(bottleneck(p), "load_imbalance");
  p.imbalance = 1.0;
  EXPECT_EQ(bottleneck(p), "latency");
  p.host_preprocess = 300;
  EXPECT_EQ(bottleneck(p), "host_preprocessing");
}

}  // namespace
}  // namespace rtm
