#include "render/reference.h"

#include <gtest/gtest.h>

namespace rtm {
namespace {

TEST(CountDifferences, NoneForTheSameWork) {
  TraceCounts a;
  a.rays = {64, 100, 20, 0};
  a.voxel_steps = 500;
  EXPECT_TRUE(count_differences(a, a).empty());
}

TEST(CountDifferences, EachCountThatDiffersWithBothValues) {
  TraceCounts a, b;
  a.rays = b.rays = {64, 100, 20, 0};
  b.rays[1] = 103;
  a.voxel_steps = 500;
  b.voxel_steps = 512;
  a.clip_tests = 7;
  const std::vector<CountDifference> d = count_differences(a, b);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].what, "shadow rays");
  EXPECT_EQ(d[0].a, 100u);
  EXPECT_EQ(d[0].b, 103u);
  EXPECT_EQ(d[1].what, "voxel steps");
  EXPECT_EQ(d[2].what, "clip tests");
  EXPECT_EQ(d[2].b, 0u);
}

}  // namespace
}  // namespace rtm
