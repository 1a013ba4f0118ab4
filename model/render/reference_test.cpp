#include "render/reference.h"

#include <chrono>
#include <string>

#include <gtest/gtest.h>

#include "scene/scene.h"

namespace rtm {
namespace {

/// One pixel inside a box of mirrors round a glass sphere, threshold 0, max_depth 255: every hit
/// on the sphere reflects and transmits, so the pixel's tree (depth first, little memory) would
/// take longer than any render could.
Scene glass_box() {
  std::string y =
      "name: glass-box\n"
      "camera: {eye: [0, 0, 0.5], look_at: [0.3, 0.2, -0.3], up: [0, 1, 0], fov: 40, resolution: "
      "[1, 1]}\n"
      "lights: [{position: [0.5, 0.8, 0.5], color: [1, 1, 1]}]\n"
      "materials:\n"
      "  mirror: {color: [1, 1, 1], ambient: 0, diffuse: 0, specular: 1}\n"
      "  glass: {color: [1, 0.5, 0.2], ambient: 0.2, diffuse: 0.8, specular: 1, transmission: 1, "
      "ior: 1.5}\n"
      "render: {threshold: 0, max_depth: 255}\n"
      "primitives:\n";
  for (const char* wall : {"[1, 0, 0], d: 1, box: {min: [-1.1, -1.1, -1.1], max: [-0.9, 1.1, 1.1]}",
                           "[-1, 0, 0], d: 1, box: {min: [0.9, -1.1, -1.1], max: [1.1, 1.1, 1.1]}",
                           "[0, 1, 0], d: 1, box: {min: [-1.1, -1.1, -1.1], max: [1.1, -0.9, 1.1]}",
                           "[0, -1, 0], d: 1, box: {min: [-1.1, 0.9, -1.1], max: [1.1, 1.1, 1.1]}",
                           "[0, 0, 1], d: 1, box: {min: [-1.1, -1.1, -1.1], max: [1.1, 1.1, -0.9]}",
                           "[0, 0, -1], d: 1, box: {min: [-1.1, -1.1, 0.9], max: [1.1, 1.1, 1.1]}"})
    y += std::string("  - {plane: {normal: ") + wall + "}, material: mirror}\n";
  y += "  - {sphere: {center: [0.3, 0.2, -0.3], radius: 0.3}, material: glass}\n";
  Scene s = parse_native(y, "glass-box.yaml");
  validate(s);
  return s;
}

TEST(ReferenceWatch, AWorkBudgetStopsATreeThatNeverEnds) {
  const Scene s = glass_box();
  const Grid g = build_grid(s.primitives, s.grid);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    render_reference(s, g, 2, ReferenceWatch{false, 0, 200000});
    FAIL() << "the render finished";
  } catch (const BudgetExceeded& e) {
    EXPECT_EQ(std::string(e.what()),
              "the reference render stopped at its work budget of 200000 rays (--max-rays), with 0 "
              "of 1 pixels done: "
              "the ray trees grow with max_depth 255 and threshold 0");
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10);
}

// The watch reads the process's size every 50 ms: below what a test program holds, the first look
// stops it.
TEST(ReferenceWatch, AMemoryBudgetBelowWhatTheProcessHoldsStopsIt) {
  const Scene s = glass_box();
  const Grid g = build_grid(s.primitives, s.grid);
  try {
    render_reference(s, g, 1, ReferenceWatch{false, 1 << 20, 0});
    FAIL() << "the render finished";
  } catch (const BudgetExceeded& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("the reference render stopped holding ", 0), 0u) << m;
    EXPECT_NE(m.find(" MiB, more than its memory budget of 1.0 MiB (--max-memory), with 0 of 1 "
                     "pixels done and "),
              std::string::npos)
        << m;
  }
}

// Budgets the render stays within change nothing.
TEST(ReferenceWatch, ARenderWithinItsBudgetsIsTheSame) {
  Scene s = load_scene(RTM_SOURCE_DIR "/scenes/spd/balls-1.nff");
  set_resolution(s, 24, 24);
  const Grid g = build_grid(s.primitives, s.grid);
  const ReferenceResult free = render_reference(s, g, 2);
  const ReferenceResult watched =
      render_reference(s, g, 2, ReferenceWatch{false, uint64_t(1) << 40, 1000000000});
  EXPECT_TRUE(count_differences(free.counts, watched.counts).empty());
  EXPECT_EQ(free.image.ids, watched.image.ids);
  ASSERT_EQ(free.image.rgb.size(), watched.image.rgb.size());
  for (size_t i = 0; i < free.image.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(free.image.rgb[i][c], watched.image.rgb[i][c]) << i;
}

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
