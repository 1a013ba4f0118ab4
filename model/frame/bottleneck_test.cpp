#include "frame/bottleneck.h"

#include "units/unit_table.h"

#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace rtm {
namespace {

FrameProfile busy_pes() {
  FrameProfile p;
  p.total = 1000;
  p.host_preprocess = 50;
  p.transfer = 20;
  p.gather = 10;
  p.issue[UnitKind::Mac] = 0.3;
  p.issue[UnitKind::Search] = 0.2;
  return p;
}

TEST(Bottleneck, HostOrLinkTakingHalfTheFrame) {
  FrameProfile both = busy_pes();
  both.host_preprocess = 300;
  both.transfer = 250;
  EXPECT_EQ(bottleneck(both).name, "host_preprocessing");
  FrameProfile p = busy_pes();
  p.host_preprocess = 600;
  EXPECT_EQ(bottleneck(p).name, "host_preprocessing");
  p = busy_pes();
  p.transfer = 300;
  p.gather = 250;
  EXPECT_EQ(bottleneck(p).name, "interconnect");
}

// Several frames: the stages overlap, so the longest a frame sets the pace, however much the
// others take; of the PEs', their voxelisation or their work.
TEST(Bottleneck, PipelinedFramesNameTheLongestStage) {
  FrameProfile p = busy_pes();
  p.pipelined = true;
  p.issue[UnitKind::Mac] = 0.9;
  p.host_preprocess = 300;
  p.transfer = 250;
  p.pe = 950;
  EXPECT_EQ(bottleneck(p).name, "mac") << "host and link together more than half, the PEs longer";
  p.pipelined = false;
  EXPECT_EQ(bottleneck(p).name, "host_preprocessing") << "one frame: the serial parts add up";
  p.pipelined = true;
  p.pe = 200;
  EXPECT_EQ(bottleneck(p).name, "host_preprocessing");
  p.transfer = 400;
  EXPECT_EQ(bottleneck(p).name, "interconnect");
  p.pe = 300;
  p.pe_voxelisation = 350;
  EXPECT_EQ(bottleneck(p).name, "pe_voxelisation") << "the PEs' 650 a frame, most of it building";
}

TEST(Bottleneck, AStreamedGatherIsNamedWithItsTail) {
  FrameProfile p = busy_pes();
  p.transfer = 300;
  p.gather = 250;
  EXPECT_EQ(bottleneck(p).reason, "host pre-processing 5.0% and the link 55.0% of the frame");
  p.gather_streamed = true;
  EXPECT_EQ(bottleneck(p).name, "interconnect");
  EXPECT_EQ(bottleneck(p).reason,
            "host pre-processing 5.0% and the link 55.0% of the frame (the streamed gather's tail "
            "after the last PE 25.0%)");
}

TEST(Bottleneck, ThePesVoxelisationWhenItTakesTheMost) {
  FrameProfile p = busy_pes();
  p.pe_voxelisation = 450;
  EXPECT_EQ(bottleneck(p).name, "pe_voxelisation");
  EXPECT_EQ(bottleneck(p).reason,
            "host pre-processing 5.0%, the link 3.0% and the PEs' voxelisation 45.0% of the frame");
  p.pe_voxelisation = 100;
  p.transfer = 400;
  EXPECT_EQ(bottleneck(p).name, "interconnect");
  p.pe_voxelisation = 300;  // none of them half the frame alone, the largest >= 25%
  p.transfer = 20;
  p.issue[UnitKind::Mac] = 0.3;
  EXPECT_EQ(bottleneck(p).name, "pe_voxelisation");
}

TEST(Bottleneck, TheBusiestUnitWhenItIsSaturated) {
  FrameProfile p = busy_pes();
  p.issue[UnitKind::Mac] = 0.92;
  EXPECT_EQ(bottleneck(p).name, "mac");
  p.issue[UnitKind::Mac] = 0.5;
  p.issue[UnitKind::Search] = 0.7;
  EXPECT_EQ(bottleneck(p).name, "search");
  p.issue[UnitKind::Search] = 0.1;
  p.issue[UnitKind::Shading] = 0.65;
  EXPECT_EQ(bottleneck(p).name, "shading");
}

TEST(Bottleneck, APipelinedUnitHoldingItemsAllTheTimeIsNotSaturated) {
  FrameProfile p = busy_pes();
  p.busy[UnitKind::Root] = 0.98;  // a long latency, items inside nearly always ...
  p.issue[UnitKind::Root] = 0.2;  // ... but its entry mostly free
  p.issue[UnitKind::Mac] = 0.7;
  EXPECT_EQ(bottleneck(p).name, "mac");
}

TEST(Bottleneck, BackPressureImbalanceAndLatency) {
  FrameProfile p = busy_pes();
  p.credit_stall = 0.5;
  EXPECT_EQ(bottleneck(p).name, "loop_credits");
  p.credit_stall = 0;
  p.tile_wait = 0.4;
  p.imbalance = 1.8;
  EXPECT_EQ(bottleneck(p).name, "waiting_for_tiles");
  p.tile_wait = 0.1;
  EXPECT_EQ(bottleneck(p).name, "load_imbalance");
  p.imbalance = 1.0;
  EXPECT_EQ(bottleneck(p).name, "latency");
  p.host_preprocess = 300;
  EXPECT_EQ(bottleneck(p).name, "host_preprocessing");
}

TEST(Bottleneck, TheReasonGivesTheFiguresThatDecidedIt) {
  FrameProfile p = busy_pes();
  p.issue[UnitKind::Mac] = 0.875;
  EXPECT_EQ(bottleneck(p).reason, "its entry taken 87.5% of the PEs' working windows");
  p.issue[UnitKind::Mac] = 0.41;
  EXPECT_EQ(bottleneck(p).reason, "no unit saturated (the busiest, mac, 41.0%)");
  p.imbalance = 1.5;
  EXPECT_EQ(bottleneck(p).reason,
            "the longest PE works 1.50 x the mean; no unit saturated (the busiest, mac, 41.0%)");
  p.imbalance = 1;
  p.credit_stall = 0.35;
  EXPECT_EQ(bottleneck(p).reason,
            "the front buffer had rays but no credit 35.0% of the PEs' working windows; no unit "
            "saturated (the "
            "busiest, mac, 41.0%)");
  p = busy_pes();
  p.host_preprocess = 600;
  EXPECT_EQ(bottleneck(p).reason, "host pre-processing 60.0% and the link 3.0% of the frame");
}

// Local memory limits the frame when the units' reads take most of their item-cycles, or results
// wait for data half the working window, even with a unit's entry nearly always taken.
TEST(Bottleneck, LocalMemoryWhenReadsOrWaitsDominate) {
  FrameProfile p = busy_pes();
  p.issue[UnitKind::Mac] = 0.9;
  p.memory_access = 0.6;
  p.memory_port = 0.25;
  EXPECT_EQ(bottleneck(p).name, "memory");
  EXPECT_EQ(
      bottleneck(p).reason,
      "reads of local memory 60.0% of the units' item-cycles, results waiting for it 0.0% of the "
      "PEs' working windows (summed over the units); the busiest port busy 25.0% of the frame");
  p.memory_access = 0.1;
  p.memory_wait = 0.8;
  EXPECT_EQ(bottleneck(p).name, "memory");
  p.memory_wait = 0.4;
  EXPECT_EQ(bottleneck(p).name, "mac") << "neither share reaches half";
}

// Each declared name is the verdict of some profile, and every verdict is a declared name.
TEST(Bottleneck, EveryDeclaredNameIsAVerdict) {
  std::vector<FrameProfile> profiles;
  for (const UnitSpec& u : unit_table()) {
    if (!u.in_utilisation) continue;
    FrameProfile p = busy_pes();
    p.issue = {};
    p.issue[u.kind] = 0.9;
    profiles.push_back(p);
  }
  FrameProfile p = busy_pes();
  profiles.push_back(p);  // latency
  p.credit_stall = 0.5;
  profiles.push_back(p);
  p = busy_pes();
  p.imbalance = 2;
  profiles.push_back(p);
  p = busy_pes();
  p.host_preprocess = 600;
  profiles.push_back(p);
  p = busy_pes();
  p.transfer = 600;
  profiles.push_back(p);
  p = busy_pes();
  p.memory_access = 0.7;
  profiles.push_back(p);
  p = busy_pes();
  p.pe_voxelisation = 600;
  profiles.push_back(p);
  p = busy_pes();
  p.tile_wait = 0.5;
  profiles.push_back(p);
  std::set<std::string> verdicts;
  for (const FrameProfile& q : profiles) verdicts.insert(bottleneck(q).name);
  EXPECT_EQ(verdicts, std::set<std::string>(bottleneck_names().begin(), bottleneck_names().end()));
}

}  // namespace
}  // namespace rtm
