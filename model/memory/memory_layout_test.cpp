// A PE's local memory laid out from the real data, on a scene whose bytes can be counted by hand.
#include "memory/memory_layout.h"

#include <gtest/gtest.h>

#include "memory/scene_image.h"

namespace rtm {
namespace {

/// Two spheres, one light, one material, a 2x1x1 grid with each sphere in its own voxel.
struct Fixture {
  Scene scene;
  Grid grid;
  Fixture() {
    scene.materials.push_back(Material{});
    scene.lights.push_back(Light{});
    scene.primitives.push_back(make_sphere({0.5, 0.5, 0.5}, 0.4));
    scene.primitives.push_back(make_sphere({1.5, 0.5, 0.5}, 0.4));
    GridOptions o;
    o.resolution = {2, 1, 1};
    grid = build_grid(scene.primitives, o);
  }
};

TEST(MemoryLayout, SectionsAreTheSceneCopyThePrimaryRaysAndTheFrameBuffer) {
  Fixture f;
  MachineConfig c;
  c.precision = Precision::Fp32;
  c.mac_schedule = MachineConfig::MacSchedule::Full;
  c.local_memory_bytes = 4096;
  const SceneImage image(f.scene, f.grid, c);
  const MemoryLayout m = memory_layout(image, 10, c);
  // Per primitive 13 RAM words, 3 centre, 0 clips, 6 bounds, 1 material: 23 words of 4 bytes.
  ASSERT_EQ(m.sections.size(), 5u);
  EXPECT_EQ(m.sections[0].name, "primitives");
  EXPECT_EQ(m.sections[0].bytes, 2u * 23 * 4);
  // One offset per voxel, one id per reference.
  EXPECT_EQ(m.sections[1].bytes, 4 * (f.grid.start.size() + f.grid.items.size()));
  EXPECT_EQ(m.sections[2].bytes, (6u + 8u) * 4);
  EXPECT_EQ(m.sections[3].bytes, 10 * kRayRecordBytes);
  EXPECT_EQ(m.sections[4].bytes, 10 * kPixelRecordBytes);
  const uint64_t used = 184 + m.sections[1].bytes + 56 + 280 + 160;
  EXPECT_EQ(m.used, used);
  EXPECT_EQ(m.sections[0].bytes + m.sections[1].bytes + m.sections[2].bytes,
            image.bytes);  // what the link carries
  EXPECT_TRUE(m.fits());
  EXPECT_EQ(m.spill_bytes(), 4096 - used);
  EXPECT_EQ(m.spill_rays(), (4096 - used) / kSpillRecordBytes);
}

TEST(MemoryLayout, RaysGeneratedOnThePeNeedOnlyTheCameraAndAFullMemoryLeavesNoSpillArea) {
  Fixture f;
  MachineConfig c;
  c.ray_generation = MachineConfig::RayGeneration::Pe;
  const SceneImage image(f.scene, f.grid, c);
  c.local_memory_bytes = 1024;
  const MemoryLayout m = memory_layout(image, 1000, c);
  EXPECT_EQ(m.sections[3].bytes, kCameraRecordBytes);
  EXPECT_EQ(m.sections[4].bytes, 1000 * kPixelRecordBytes);
  EXPECT_FALSE(m.fits());
  EXPECT_EQ(m.spill_bytes(), 0u);
  EXPECT_EQ(m.spill_rays(), 0u);
  EXPECT_NE(m.describe().find("frame buffer 16000 B"), std::string::npos) << m.describe();
}

}  // namespace
}  // namespace rtm
