// The origin latch through a PE's units, one ray at a time (pe_tracer.h): a hit on the face
// between two voxels is found from either side of it.
#include <gtest/gtest.h>

#include <vector>

#include "geom/test_grid.h"
#include "error/pe_tracer.h"

namespace rtm {
namespace {

using test::unit_grid;

// A square in the plane x = 1, the face between a grid's two voxels, listed in both: every ray
// from the first voxel must find it in one of them. With the advanced origin latch each voxel
// measures its roots from its own entry, and float rounding put some hits past the first voxel's
// exit and before the second's entry (render/voxel_test.h, kAdvancedWindowReach).
TEST(OriginLatch, TheAdvancedLatchFindsAHitOnItsVoxelsEntryFace) {
  Scene s;
  s.materials.push_back(Material{});
  s.primitives.push_back(make_polygon({{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}));
  Grid g = unit_grid({2, 1, 1});
  g.items = {0, 0};  // as the grid lists it: it touches both voxels
  g.start = {0, 1, 2};
  for (const char* latch : {"origin_latch=wide", "origin_latch=advance"}) {
    MachineConfig c;
    set_config_assignment(c, "precision=fp32");
    set_config_assignment(c, latch);
    PeTracer pe(s, g, c);
    int missed = 0;
    for (int i = 0; i < 2000; ++i) {
      Ray r;
      r.origin = {0.5 + 0.0002 * i, 0.2 + 0.0003 * i, 0.8 - 0.0003 * i};
      r.dir = normalize(Vec3{1, 0.01 + 1e-4 * i, 0.07});
      RayResult out;
      pe.trace(r, out);
      missed += out.end != RayResult::End::Hit;
    }
    EXPECT_EQ(missed, 0) << latch;
  }
}

}  // namespace
}  // namespace rtm
