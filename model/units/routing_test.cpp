// The routing of §4.2 and §5.1 on hand-built rays, without the kernel.
#include "units/routing.h"

#include <gtest/gtest.h>

namespace rtm {
namespace {

/// A 5x1x1 grid over x in [0, 5]: a sphere in voxel 2, tiny spheres in voxels 0 and 4 that fix
/// the grid's extent, voxels 1 and 3 empty.
struct Fixture {
  Scene scene;
  Grid grid;
  Fixture() {
    scene.materials.push_back(Material{});
    scene.primitives.push_back(make_sphere({2.5, 0.5, 0.5}, 0.4));
    scene.primitives.push_back(make_sphere({0.01, 0.01, 0.01}, 0.01));
    scene.primitives.push_back(make_sphere({4.99, 0.99, 0.99}, 0.01));
    GridOptions o;
    o.resolution = {5, 1, 1};
    grid = build_grid(scene.primitives, o);
  }
  MachineRay ray(RayKind kind, Vec3 origin, Vec3 dir, double t_max = kInf) {
    MachineRay r;
    r.ray.kind = kind;
    r.ray.origin = origin;
    r.ray.dir = normalize(dir);
    r.ray.t_max = t_max;
    return r;
  }
};

int cell_x(const MachineRay& r) { return r.examined.cell[0]; }

TEST(Routing, EmptyVoxelsAreFedBackThenTheOccupiedOneGoesToIntersection) {
  Fixture f;
  MachineRay r = f.ray(RayKind::Primary, {1.5, 0.5, 0.5}, {1, 0, 0});  // starts in voxel 1 (empty)
  ASSERT_TRUE(search_pass(f.grid, r));
  EXPECT_EQ(cell_x(r), 1);
  EXPECT_EQ(search_route(f.scene, f.grid, r, true), Route::Feedback);
  ASSERT_TRUE(search_pass(f.grid, r));
  EXPECT_EQ(cell_x(r), 2);
  EXPECT_EQ(search_route(f.scene, f.grid, r, true), Route::Intersect);
}

TEST(Routing, PrimaryRayHittingGoesToShading) {
  Fixture f;
  MachineRay r =
      f.ray(RayKind::Primary, {2.05, 0.5, 0.5}, {1, 0, 0});  // inside the sphere, voxel 2
  ASSERT_TRUE(search_pass(f.grid, r));
  VoxelHit h;
  h.hit = true;
  h.t = 0.85;
  h.prim = 0;
  EXPECT_EQ(intersection_route(f.scene, r, h), Route::Shade);
  EXPECT_EQ(r.arrival, MachineRay::Arrival::Hit);
  EXPECT_EQ(r.prim, 0u);
  EXPECT_DOUBLE_EQ(r.t_hit, 0.85);
}

TEST(Routing, MissInANonLastVoxelFeedsBack) {
  Fixture f;
  MachineRay r =
      f.ray(RayKind::Reflected, {2.5, 0.95, 0.5}, {-1, 0, 0});  // voxel 2, heading to voxel 1
  ASSERT_TRUE(search_pass(f.grid, r));
  EXPECT_FALSE(r.last);
  EXPECT_EQ(intersection_route(f.scene, r, VoxelHit{}), Route::Feedback);
}

TEST(Routing, ShadowRayBlockedEnds) {
  Fixture f;
  MachineRay r = f.ray(RayKind::Shadow, {1.5, 0.5, 0.5}, {1, 0, 0}, 10.0);
  ASSERT_TRUE(search_pass(f.grid, r));
  ASSERT_TRUE(search_pass(f.grid, r));
  VoxelHit h;
  h.hit = true;
  h.t = 0.6;
  EXPECT_EQ(intersection_route(f.scene, r, h), Route::End);
}

TEST(Routing, ShadowRayLeavingTheGridReachesItsLight) {
  Fixture f;
  MachineRay r =
      f.ray(RayKind::Shadow, {3.5, 0.5, 0.5}, {0, 1, 0}, 10.0);  // leaves the grid after voxel 3
  ASSERT_TRUE(search_pass(f.grid, r));
  EXPECT_TRUE(r.last);
  EXPECT_EQ(search_route(f.scene, f.grid, r, true), Route::Shade);
  EXPECT_EQ(r.arrival, MachineRay::Arrival::LightReached);
}

TEST(Routing, ShadowRayMissingInItsLastOccupiedVoxelReachesItsLight) {
  Fixture f;
  // The light sits inside voxel 2: that voxel is the last, and nothing there blocks.
  MachineRay r = f.ray(RayKind::Shadow, {1.5, 0.95, 0.5}, {1, 0, 0}, 1.0);
  ASSERT_TRUE(search_pass(f.grid, r));
  EXPECT_FALSE(r.last);
  ASSERT_TRUE(search_pass(f.grid, r));
  EXPECT_TRUE(r.last);
  EXPECT_EQ(search_route(f.scene, f.grid, r, true), Route::Intersect);
  EXPECT_EQ(intersection_route(f.scene, r, VoxelHit{}), Route::Shade);
  EXPECT_EQ(r.arrival, MachineRay::Arrival::LightReached);
}

TEST(Routing, PrimaryRayLeavingTheGridEndsOrTakesTheBackground) {
  Fixture f;
  MachineRay r = f.ray(RayKind::Primary, {3.5, 0.5, 0.5}, {0, 1, 0});
  ASSERT_TRUE(search_pass(f.grid, r));
  EXPECT_EQ(search_route(f.scene, f.grid, r, true),
            Route::End);  // black background: nothing to add
  f.scene.background = {0.1, 0.2, 0.3};
  MachineRay q = f.ray(RayKind::Primary, {3.5, 0.5, 0.5}, {0, 1, 0});
  ASSERT_TRUE(search_pass(f.grid, q));
  EXPECT_EQ(search_route(f.scene, f.grid, q, true), Route::Shade);
  EXPECT_EQ(q.arrival, MachineRay::Arrival::Missed);
}

TEST(Routing, MissInTheLastOccupiedVoxelEnds) {
  Fixture f;
  MachineRay r = f.ray(RayKind::Transmitted, {3.5, 0.95, 0.5}, {-1, 0, 0}, kInf);
  // Walk right to left: voxels 3, 2, 1, 0; voxel 0 holds the tiny sphere and is the last.
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(search_pass(f.grid, r));
  EXPECT_EQ(cell_x(r), 0);
  EXPECT_TRUE(r.last);
  EXPECT_EQ(intersection_route(f.scene, r, VoxelHit{}), Route::End);
}

TEST(Routing, RayMissingTheGridEndsWithoutAVoxel) {
  Fixture f;
  MachineRay r = f.ray(RayKind::Primary, {0, 5, 0}, {0, 1, 0});
  EXPECT_FALSE(search_pass(f.grid, r));
  EXPECT_EQ(search_route(f.scene, f.grid, r, false), Route::End);
  MachineRay s = f.ray(RayKind::Shadow, {0, 5, 0}, {0, 1, 0}, 3.0);
  EXPECT_FALSE(search_pass(f.grid, s));
  EXPECT_EQ(search_route(f.scene, f.grid, s, false), Route::Shade);
}

}  // namespace
}  // namespace rtm
