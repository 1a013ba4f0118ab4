// The PE's units in the grid's frame (pe_frame = grid, scene/grid_frame.h) against the world
// frame, on hand-built rays a million units from the origin: a small sphere just past a voxel's
// entry face, grazing rays, and shadow rays born on a surface. The default fp32 machine must do
// there what it does at the origin; world coordinates are measured for docs/numerics.md.
#include <gtest/gtest.h>

#include <iostream>

#include "error/pe_tracer.h"
#include "geom/grid.h"
#include "scene/grid_frame.h"

namespace rtm {
namespace {

constexpr double kFar = 1e6;
constexpr double kRadius = 1e-3;

/// Two voxels of edge 1 from (kFar, kFar, kFar) along x; the sphere lies in the second only,
/// its near side `gap` past the face between them.
struct FarScene {
  Scene scene;
  Grid grid;
  Vec3 centre;
  explicit FarScene(double gap) {
    scene.materials.push_back(Material{});
    centre = {kFar + 1 + gap + kRadius, kFar + 0.5, kFar + 0.5};
    scene.primitives.push_back(make_sphere(centre, kRadius));
    scene.lights.push_back({{kFar + 0.2, kFar + 0.9, kFar + 0.7}, {1, 1, 1}});
    grid.n = {2, 1, 1};
    grid.box = {{kFar, kFar, kFar}, {kFar + 2, kFar + 1, kFar + 1}};
    grid.cell = {1, 1, 1};
    grid.start = {0, 0, 1};
    grid.items = {0};
  }
};

MachineConfig machine(PeFrame frame, Precision p = Precision::Fp32) {
  MachineConfig c;
  c.pe_frame = frame;
  c.precision = p;
  return c;
}

/// Rays from the first voxel at the sphere, `aim` radii off its axis (in y), traced through a PE's
/// units in the machine's frame; how many end as `end`.
int count(const FarScene& f, const MachineConfig& c, double aim, RayResult::End end,
          int rays = 400) {
  const FramedScene v = framed(f.scene, f.grid, c.pe_frame);
  const GridFrame frame = c.pe_frame == PeFrame::Grid ? grid_frame(f.grid.box) : GridFrame{};
  PeTracer pe(v.scene, v.grid, c);
  int n = 0;
  for (int i = 0; i < rays; ++i) {
    const Vec3 from{kFar + 0.3 + 0.001 * i, kFar + 0.2 + 0.0007 * i, kFar + 0.8 - 0.0009 * i};
    const Vec3 side = normalize(cross(f.centre - from, Vec3{0, 0, 1}));
    Ray r;
    r.origin = frame.point(from);
    r.dir = normalize(frame.point(f.centre + aim * kRadius * side) - r.origin);
    RayResult out;
    pe.trace(r, out);
    n += out.end == end;
  }
  return n;
}

TEST(PeFrame, AHitJustPastAVoxelsEntryFaceAMillionAwayIsFound) {
  for (double gap : {0.0, 1e-9, 1e-6}) {
    const FarScene f(gap);
    EXPECT_EQ(count(f, machine(PeFrame::Grid), 0.5, RayResult::End::Hit), 400) << "gap " << gap;
    EXPECT_EQ(count(f, machine(PeFrame::Grid, Precision::Fp64), 0.5, RayResult::End::Hit), 400)
        << "gap " << gap;
    std::cout << "[ numerics ] gap " << gap << ": world frame, fp32, "
              << count(f, machine(PeFrame::World), 0.5, RayResult::End::Hit) << " of 400 hit\n";
  }
}

TEST(PeFrame, GrazingRaysAMillionAwayAreClassifiedAsInDouble) {
  const FarScene f(0.25);
  for (double aim : {0.98, 1.02}) {
    const int fp64 = count(f, machine(PeFrame::Grid, Precision::Fp64), aim, RayResult::End::Hit);
    EXPECT_EQ(fp64, aim < 1 ? 400 : 0);
    EXPECT_EQ(count(f, machine(PeFrame::Grid), aim, RayResult::End::Hit), fp64) << "aim " << aim;
    std::cout << "[ numerics ] aim " << aim << " r: world frame, fp32, "
              << count(f, machine(PeFrame::World), aim, RayResult::End::Hit) << " of 400 hit, fp64 "
              << fp64 << "\n";
  }
}

TEST(PeFrame, ShadowRaysBornOnASurfaceAMillionAwayDoNotFindIt) {
  // The light is on the rays' side of the sphere: every shadow ray from the lit side reaches it.
  const FarScene f(0.25);
  const MachineConfig c = machine(PeFrame::Grid);
  const FramedScene v = framed(f.scene, f.grid, c.pe_frame);
  const GridFrame frame = grid_frame(f.grid.box);
  PeTracer pe(v.scene, v.grid, c);
  int shadow = 0, reached = 0;
  for (int i = 0; i < 400; ++i) {
    Ray r;
    r.origin =
        frame.point({kFar + 0.2, kFar + 0.5 + 0.0004 * (i - 200), kFar + 0.6 - 0.0002 * (i % 50)});
    r.dir = normalize(frame.point(f.centre) - r.origin);
    RayResult out;
    pe.trace(r, out);
    ASSERT_EQ(out.end, RayResult::End::Hit);
    for (const Ray& child : out.spawned) {
      if (child.kind != RayKind::Shadow) continue;
      ++shadow;
      RayResult s;
      pe.trace(child, s);
      reached += s.end == RayResult::End::LightReached;
    }
  }
  EXPECT_GT(shadow, 0);
  EXPECT_EQ(reached, shadow);
}

TEST(GridFrame, MapsTheGridOntoTheUnitCubeAndKeepsEverySurface) {
  const FarScene f(0.25);
  const GridFrame frame = grid_frame(f.grid.box);
  EXPECT_EQ(frame.scale, 0.5);
  const Grid g = in_frame(f.grid, frame);
  EXPECT_EQ(g.box.lo, Vec3(0));
  EXPECT_EQ(g.box.hi, Vec3(1, 0.5, 0.5));
  EXPECT_EQ(g.cell, Vec3(0.5));
  const Primitive p = in_frame(f.scene.primitives[0], frame);
  // A point on the sphere, in the frame, is on the framed sphere to fp64 rounding of the frame.
  const Vec3 on = f.centre + Vec3(0, kRadius, 0);
  EXPECT_NEAR(p.value_at(frame.point(on)) / (kRadius * frame.scale) / (kRadius * frame.scale), 0,
              1e-6);
  EXPECT_NEAR(p.q.value(frame.point(on)) / (kRadius * frame.scale) / (kRadius * frame.scale), 0,
              1e-6);
  EXPECT_NEAR(p.r0, kRadius * 0.5, 1e-18);
  EXPECT_TRUE(framed(f.scene, f.grid, PeFrame::World).scene.primitives[0].bounds.lo ==
              f.scene.primitives[0].bounds.lo);
}

}  // namespace
}  // namespace rtm
