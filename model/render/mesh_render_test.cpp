// A mesh file rendered by the reference renderer as the same polygons in NFF: the whole path from
// Assimp's import to the image.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "geom/grid.h"
#include "render/reference.h"
#include "scene/mesh_test_files.h"
#include "scene/scene.h"

namespace rtm {
namespace {

namespace fs = std::filesystem;

class MeshRender : public test::MeshFileTest {};
using test::kObj;

TEST_F(MeshRender, ObjRendersAsTheSameNffPolygons) {
  // A concave-free mesh of two quads and a triangle, as OBJ (faces in the same order) and as NFF
  // polygons with the OBJ's triangulation.
  const std::string nff =
      "v\nfrom 0.5 0.5 4\nat 0.5 0.5 0\nup 0 1 0\nangle 40\nhither 1\nresolution 32 32\n"
      "l 2 3 5\nf 0.8 0.8 0.8 0.9 0 0 0 1\n"
      "p 3\n0 0 0\n1 0 0\n1 1 0\n"
      "p 3\n0 0 0\n1 1 0\n0 1 0\n"
      "p 3\n0 0 -1\n1 0 -1\n0 1 -1\n";
  const Scene a = load_scene(write("same.nff", nff));
  Scene b = load_scene(write("same.obj", kObj));
  ASSERT_EQ(a.primitives.size(), b.primitives.size());
  b.camera = a.camera;
  b.lights = a.lights;
  b.ambient_light = a.ambient_light;
  b.materials = a.materials;
  b.threshold = a.threshold;
  b.max_depth = a.max_depth;
  for (Primitive& p : b.primitives) p.material = 0;
  const Grid ga = build_grid(a.primitives, a.grid), gb = build_grid(b.primitives, b.grid);
  const ReferenceResult ra = render_reference(a, ga, 1), rb = render_reference(b, gb, 1);
  EXPECT_EQ(ra.image.rgb, rb.image.rgb);
  EXPECT_EQ(ra.image.ids, rb.image.ids);
  int hits = 0;
  for (const int32_t id : ra.image.ids) hits += id >= 0;
  EXPECT_GT(hits, 50);  // the test looks at the mesh, not at the background
}

}  // namespace
}  // namespace rtm
