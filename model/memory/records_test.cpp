// What each request moves and where each record lies: the per-record sizes add up to the sections
// SceneImage and memory_layout count, in either precision and schedule.
#include "memory/records.h"

#include <gtest/gtest.h>

#include "memory/scene_image.h"

namespace rtm {
namespace {

/// The default scene and a clipped cone, so records with clips are counted too.
Scene scene_with_clips() {
  Scene s = default_scene();
  Primitive cone = make_cone({0, 0, 0}, 1, {0, 2, 0}, 0.2);
  cone.clips.push_back({{1, 0, 0}, -0.5});
  cone.clips.push_back({{0, 0, 1}, 0.25});
  s.primitives.push_back(cone);
  return s;
}

TEST(Records, TheRecordsAddUpToTheSectionsOfTheLayout) {
  const Scene s = scene_with_clips();
  GridOptions o;
  o.resolution = {5, 4, 3};
  const Grid g = build_grid(s.primitives, o);
  ASSERT_GT(g.items.size(), s.primitives.size());
  for (Precision p : {Precision::Fp32, Precision::Fp64})
    for (auto schedule : {MachineConfig::MacSchedule::Sparse, MachineConfig::MacSchedule::Full})
      for (bool recentre : {true, false}) {
        MachineConfig c;
        c.precision = p;
        c.mac_schedule = schedule;
        c.recentre = recentre;
        const SceneImage image(s, g, c);
        const MemoryAddresses a(image, 7, c);
        const MemoryLayout l = memory_layout(image, 7, c);
        const std::string what = std::string(to_string(p)) + " " + to_string(schedule) + " " +
                                 (recentre ? "recentred" : "world");
        ASSERT_EQ(l.sections[0].name, "primitives");
        ASSERT_EQ(l.sections[1].name, "voxel data");
        ASSERT_EQ(l.sections[2].name, "lights and materials");
        ASSERT_EQ(l.sections[3].name, "primary rays");
        ASSERT_EQ(l.sections[4].name, "frame buffer");
        EXPECT_EQ(a.voxel_offsets - a.coef_record(0), image.primitive_bytes) << what;
        EXPECT_EQ(voxel_data_bytes(g.start.size() - 1, g.items.size()), image.voxel_bytes) << what;
        EXPECT_EQ(a.lights - a.voxel_offsets, image.voxel_bytes) << what;
        EXPECT_EQ(word_bytes(p) * (kLightRecordWords * s.lights.size() +
                                   kMaterialRecordWords * s.materials.size()),
                  image.light_bytes)
            << what;
        EXPECT_EQ(a.rays, image.bytes) << what << ": the scene copy comes first";
        EXPECT_EQ(a.frame - a.rays, 7 * kRayRecordBytes) << what;
        EXPECT_EQ(a.spill, l.used) << what;
      }
}

TEST(Records, EachRecordFollowsItsNeighbour) {
  Scene s;
  s.materials.push_back(Material{});
  s.lights.push_back(Light{});
  s.primitives.push_back(make_sphere({0, 0, 0}, 1));
  s.primitives.push_back(make_sphere({3, 0, 0}, 1));
  s.primitives[1].clips.push_back({{1, 0, 0}, -3});
  GridOptions o;
  o.resolution = {2, 1, 1};
  const Grid g = build_grid(s.primitives, o);
  ASSERT_EQ(g.start.size(), 3u);
  ASSERT_EQ(g.items.size(), 2u);
  MachineConfig c;
  c.mac_schedule = MachineConfig::MacSchedule::Full;
  // fp32, full schedule: primitive 0 is 13 + 3 + 6 + 1 = 23 words (92 bytes), primitive 1 four
  // more for its clip (108); three offsets and two ids (20); a light and a material (56).
  const MemoryAddresses a(SceneImage(s, g, c), 5, c);
  EXPECT_EQ(a.coef_record(0), 0u);
  EXPECT_EQ(a.coef_record(1), 92u);
  EXPECT_EQ(a.voxel_offsets, 200u);
  EXPECT_EQ(a.voxel_entry(1), 204u);
  EXPECT_EQ(a.voxel_lists, 212u);
  EXPECT_EQ(a.voxel_list(g.start[1]), 212u + 4 * g.start[1]);
  EXPECT_EQ(a.lights, 220u);
  EXPECT_EQ(a.rays, 276u);
  EXPECT_EQ(a.primary_ray(2), 276u + 56);
  EXPECT_EQ(a.frame, 276u + 140);
  EXPECT_EQ(a.frame_entry(4), a.frame + 64);
  EXPECT_EQ(a.spill, a.frame + 80);
  EXPECT_EQ(a.spilled_ray(1), a.spill + kSpillRecordBytes);
  c.precision = Precision::Fp64;
  EXPECT_EQ(MemoryAddresses(SceneImage(s, g, c), 5, c).coef_record(1), 184u);
}

TEST(Records, WhatEachRequestMoves) {
  EXPECT_EQ(voxel_entry_bytes(), 8u);
  EXPECT_EQ(voxel_list_bytes(5), 20u);
  EXPECT_EQ(coef_record_bytes(Precision::Fp32), 52u);
  EXPECT_EQ(coef_record_bytes(Precision::Fp64), 104u);
  EXPECT_EQ(coef_record_bytes(Precision::Fp32, 5), 20u);
  CoefRam<float> sphere{};
  sphere[0] = sphere[1] = sphere[2] = 1;
  sphere[12] = -1;
  EXPECT_EQ(coef_record_words(sphere, true), 5u) << "four non-zero words and the mask";
  EXPECT_EQ(coef_record_words(sphere, false), 13u);
  EXPECT_EQ(kBrightnessBytes, 12u);
  EXPECT_EQ(kSpillRecordBytes, 60u) << "the ray record, its walk (7 words) and its number";
}

}  // namespace
}  // namespace rtm
