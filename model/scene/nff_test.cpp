#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <sstream>
#include <tuple>

#include <gtest/gtest.h>

#include "scene/scene.h"

namespace rtm {
namespace {

// The whole SPD corpus (scenes/spd-corpus/README.md).
const std::string kSpdDir = RTM_SOURCE_DIR "/scenes/spd-corpus";

/// A minimal valid file: view, one light, one material; the test appends primitives.
const std::string kHeader =
    "v\n"
    "from 0 0 10\n"
    "at 0 0 0\n"
    "up 0 1 0\n"
    "angle 40\n"
    "hither 1\n"
    "resolution 64 48\n"
    "l 5 5 5\n"
    "f 1 0.5 0.25 0.6 0.3 20 0.1 1.3\n";  // line 9
constexpr int kHeaderLines = 9;

int count(const Scene& s, ShapeKind k) {
  int n = 0;
  for (const Primitive& p : s.primitives) n += p.kind == k;
  return n;
}

/// Distinct (colour, coefficients) tuples: SPD repeats identical `f` records.
size_t distinct_materials(const Scene& s) {
  std::set<std::tuple<double, double, double, double, double, double, double>> m;
  for (const Material& x : s.materials)
    m.insert({x.color.x, x.color.y, x.color.z, x.diffuse, x.specular, x.transmission, x.ior});
  return m.size();
}

struct SpdRow {
  const char* file;
  int spheres, cylinders, cones, polygons, polygon_vertices, lights, materials, width;
  double angle;
};

// The table in scenes/spd-corpus/README.md (materials -1: not listed for benchmark sizes).
const SpdRow kSpd[] = {
    {"balls-1.nff", 10, 0, 0, 1, 4, 3, 2, 512, 45},
    {"balls-2.nff", 91, 0, 0, 1, 4, 3, 2, 512, 45},
    {"balls-3.nff", 820, 0, 0, 1, 4, 3, 2, 512, 45},
    {"rings-1.nff", 30, 30, 0, 1, 4, 3, 7, 512, 45},
    {"rings-2.nff", 150, 150, 0, 1, 4, 3, 7, 512, 45},
    {"rings-3.nff", 420, 420, 0, 1, 4, 3, 7, 512, 45},
    {"tree-1.nff", 3, 0, 3, 1, 4, 7, 2, 512, 45},
    {"tree-2.nff", 7, 0, 7, 1, 4, 7, 2, 512, 45},
    {"tree-3.nff", 15, 0, 15, 1, 4, 7, 2, 512, 45},
    {"jacks-1.nff", 6, 3, 0, 0, 0, 1, 1, 256, 25},
    {"jacks-2.nff", 54, 27, 0, 0, 0, 1, 1, 256, 25},
    {"jacks-3.nff", 438, 219, 0, 0, 0, 1, 1, 256, 25},
    {"lattice-1.nff", 8, 12, 0, 0, 0, 6, 4, 512, 60},
    {"lattice-2.nff", 27, 54, 0, 0, 0, 6, 4, 512, 60},
    {"lattice-3.nff", 64, 144, 0, 0, 0, 6, 4, 512, 60},
    {"shells-1.nff", 361, 0, 0, 0, 0, 1, 1, 512, 45},
    {"shells-2.nff", 721, 0, 0, 0, 0, 1, 1, 512, 45},
    {"shells-3.nff", 1441, 0, 0, 0, 0, 1, 1, 512, 45},
    {"mount-1.nff", 4, 0, 0, 8, 3, 1, 2, 512, 45},
    {"mount-2.nff", 4, 0, 0, 32, 3, 1, 2, 512, 45},
    {"mount-3.nff", 4, 0, 0, 128, 3, 1, 2, 512, 45},
    {"balls-4.nff", 7381, 0, 0, 1, 4, 3, -1, 512, 45},
    {"rings-7.nff", 4200, 4200, 0, 1, 4, 3, -1, 512, 45},
    {"tree-11.nff", 4095, 0, 4095, 1, 4, 7, -1, 512, 45},
    {"jacks-4.nff", 3510, 1755, 0, 0, 0, 1, -1, 256, 25},
    {"lattice-6.nff", 343, 882, 0, 0, 0, 6, -1, 512, 60},
    {"shells-4.nff", 2881, 0, 0, 0, 0, 1, -1, 512, 45},
    {"mount-6.nff", 4, 0, 0, 8192, 3, 1, -1, 512, 45},
};

TEST(NffSpd, EveryFileMatchesTheReadmeTable) {
  ASSERT_TRUE(std::filesystem::is_directory(kSpdDir)) << kSpdDir;
  for (const SpdRow& row : kSpd) {
    SCOPED_TRACE(row.file);
    const Scene s = load_scene(kSpdDir + "/" + row.file);
    EXPECT_EQ(count(s, ShapeKind::Sphere), row.spheres);
    EXPECT_EQ(count(s, ShapeKind::Cylinder), row.cylinders);
    EXPECT_EQ(count(s, ShapeKind::Cone), row.cones);
    EXPECT_EQ(count(s, ShapeKind::Polygon), row.polygons);
    EXPECT_EQ(s.primitives.size(), size_t(row.spheres + row.cylinders + row.cones + row.polygons));
    for (const Primitive& p : s.primitives) {
      if (p.kind == ShapeKind::Polygon) {
        EXPECT_EQ(p.vertices.size(), size_t(row.polygon_vertices));
      }
    }
    EXPECT_EQ(s.lights.size(), size_t(row.lights));
    if (row.materials >= 0) {
      EXPECT_EQ(distinct_materials(s), size_t(row.materials));
    }
    EXPECT_EQ(s.camera.width, row.width);
    EXPECT_EQ(s.camera.height, row.width);
    EXPECT_EQ(s.camera.fov_deg, row.angle);
    EXPECT_EQ(s.origins.size(), s.primitives.size());
    EXPECT_EQ(s.name, std::filesystem::path(row.file).stem().string());
    EXPECT_EQ(s.max_depth, 5);
    EXPECT_EQ(s.threshold, 0);
    EXPECT_NO_THROW(validate(s));
  }
}

TEST(NffSpd, Tree1ReadsExactly) {
  ASSERT_TRUE(std::filesystem::is_directory(kSpdDir)) << kSpdDir;
  const Scene s = load_scene(kSpdDir + "/tree-1.nff");
  EXPECT_EQ(s.background, Vec3(0.078, 0.361, 0.753));
  EXPECT_EQ(s.camera.eye, Vec3(4.5, 0.4, 2));
  EXPECT_EQ(s.camera.look_at, Vec3(0, 0, 1.5));
  EXPECT_EQ(s.camera.up, Vec3(0, 0, 1));
  // Line 17 is the ground quad, line 23 the first cone: `c 0 0 0 0.15 0 0 1 0.1005`.
  ASSERT_EQ(s.primitives.size(), 7u);
  EXPECT_EQ(s.origins[0].line, 17);
  EXPECT_EQ(s.origins[1].line, 23);
  const Primitive& c = s.primitives[1];
  EXPECT_EQ(c.kind, ShapeKind::Cone);
  EXPECT_EQ(c.p0, Vec3(0, 0, 0));
  EXPECT_EQ(c.p1, Vec3(0, 0, 1));
  EXPECT_EQ(c.r0, 0.15);
  EXPECT_EQ(c.r1, 0.1005);
  EXPECT_EQ(s.materials[size_t(c.material)].name, "f@22");
  EXPECT_EQ(s.materials[size_t(c.material)].ior, 1);  // written as 0 for opaque surfaces
}

TEST(NffSemantics, ViewBlock) {
  const Scene s = parse_nff(kHeader + "s 0 0 0 1\n", "dir/view.nff");
  EXPECT_EQ(s.name, "view");
  EXPECT_EQ(s.camera.eye, Vec3(0, 0, 10));
  EXPECT_EQ(s.camera.look_at, Vec3(0, 0, 0));
  EXPECT_EQ(s.camera.up, Vec3(0, 1, 0));
  EXPECT_EQ(s.camera.fov_deg, 40);  // full edge-to-edge angle, unchanged
  EXPECT_EQ(s.camera.width, 64);
  EXPECT_EQ(s.camera.height, 48);
  EXPECT_EQ(s.background, Vec3(0, 0, 0));  // no `b`: black
  EXPECT_EQ(s.threshold, 0);
  EXPECT_EQ(s.max_depth, 5);
}

TEST(NffSemantics, ViewKeywordsInAnyOrder) {
  const Scene s = parse_nff(
      "v resolution 8 8 angle 30 hither 0 up 0 0 1 at 1 0 0 from 0 0 0\nf 1 1 1 1 0 0 0 0\ns 0 0 0 "
      "1",
      "x.nff");
  EXPECT_EQ(s.camera.look_at, Vec3(1, 0, 0));
  EXPECT_EQ(s.camera.fov_deg, 30);
}

TEST(NffSemantics, LightIntensityIsSqrtLOver2L) {
  std::string text = kHeader;  // one light already
  text += "l 1 2 3 0.5 1 0.25\nl 0 0 0\nb 0.1 0.2 0.3\n";
  const Scene s = parse_nff(text + "s 0 0 0 1\n", "l.nff");
  const double k = std::sqrt(3.0) / 6.0;
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].position, Vec3(5, 5, 5));
  EXPECT_DOUBLE_EQ(s.lights[0].color.x, k);
  EXPECT_DOUBLE_EQ(s.lights[0].color.y, k);
  EXPECT_EQ(s.lights[1].position, Vec3(1, 2, 3));
  EXPECT_DOUBLE_EQ(s.lights[1].color.x, 0.5 * k);  // an explicit colour is scaled too
  EXPECT_DOUBLE_EQ(s.lights[1].color.y, 1.0 * k);
  EXPECT_DOUBLE_EQ(s.lights[1].color.z, 0.25 * k);
  EXPECT_DOUBLE_EQ(s.ambient_light.x, k);
  EXPECT_DOUBLE_EQ(s.ambient_light.z, k);
  EXPECT_EQ(s.background, Vec3(0.1, 0.2, 0.3));
}

TEST(NffSemantics, OneLightAndNoLights) {
  Scene s = parse_nff(kHeader + "s 0 0 0 1\n", "l.nff");
  EXPECT_DOUBLE_EQ(s.lights[0].color.x, 0.5);  // sqrt(1)/2
  EXPECT_DOUBLE_EQ(s.ambient_light.y, 0.5);
  s = parse_nff(
      "v from 0 0 1 at 0 0 0 up 0 1 0 angle 45 hither 0 resolution 4 4\nf 1 1 1 1 0 0 0 0\ns 0 0 0 "
      "1",
      "none.nff");
  EXPECT_TRUE(s.lights.empty());
  EXPECT_EQ(s.ambient_light, Vec3(1, 1, 1));  // documented: full ambient when there is no light
}

TEST(NffSemantics, MaterialMapping) {
  const Scene s =
      parse_nff(kHeader + "s 0 0 0 1\nf 0.1 0.2 0.3 0.4 0.5 100000 0.9 -2\ns 3 0 0 1\n", "m.nff");
  ASSERT_EQ(s.materials.size(), 2u);
  const Material& a = s.materials[0];
  EXPECT_EQ(a.name, "f@9");
  EXPECT_EQ(a.color, Vec3(1, 0.5, 0.25));
  EXPECT_EQ(a.diffuse, 0.6);
  EXPECT_EQ(a.ambient, 0.6);  // = Kd
  EXPECT_EQ(a.specular, 0.3);
  EXPECT_EQ(a.transmission, 0.1);
  EXPECT_EQ(a.ior, 1.3);
  const Material& b = s.materials[1];
  EXPECT_EQ(b.name, "f@11");
  EXPECT_EQ(b.transmission, 0.9);
  EXPECT_EQ(b.ior, 1);  // ior <= 0 means 1
  EXPECT_EQ(s.primitives[0].material, 0);
  EXPECT_EQ(s.primitives[1].material, 1);
}

TEST(NffSemantics, ConeOnOneLineAndOnThreeLines) {
  const Scene one = parse_nff(kHeader + "c 0 0 0 1 0 2 0 0.5\n", "c.nff");
  const Scene three = parse_nff(kHeader + "c\n0 0 0 1\n0 2 0 0.5\n", "c.nff");
  ASSERT_EQ(one.primitives.size(), 1u);
  ASSERT_EQ(three.primitives.size(), 1u);
  EXPECT_EQ(one.primitives[0].kind, ShapeKind::Cone);
  EXPECT_EQ(one.primitives[0].q.c, three.primitives[0].q.c);
  EXPECT_EQ(one.primitives[0].p1, Vec3(0, 2, 0));
  EXPECT_EQ(three.primitives[0].r1, 0.5);
  EXPECT_EQ(three.origins[0].line, kHeaderLines + 1);  // the keyword's line
  const Scene cyl =
      parse_nff(kHeader + "c 0 0 0 -1 0 2 0 -1\n", "c.nff");  // inside only: same surface
  EXPECT_EQ(cyl.primitives[0].kind, ShapeKind::Cylinder);
  EXPECT_EQ(cyl.primitives[0].r0, 1);
}

TEST(NffSemantics, SpheresPolygonsAndPatches) {
  const Scene s = parse_nff(kHeader +
                                "s 1 2 3 -0.5   # inside only: same surface\n"
                                "p 3\n0 0 0\n1 0 0\n0 1 0\n"
                                "pp 4\n0 0 1 0 0 1\n1 0 1 0 0 1\n1 1 1 0 0 1\n0 1 1 0 0 1\n",
                            "p.nff");
  ASSERT_EQ(s.primitives.size(), 3u);
  EXPECT_EQ(s.primitives[0].kind, ShapeKind::Sphere);
  EXPECT_EQ(s.primitives[0].r0, 0.5);
  EXPECT_EQ(s.primitives[1].kind, ShapeKind::Polygon);
  EXPECT_EQ(s.primitives[1].vertices.size(), 3u);
  EXPECT_EQ(s.primitives[2].vertices.size(), 4u);
  EXPECT_EQ(s.primitives[2].vertices[2], Vec3(1, 1, 1));
  EXPECT_EQ(s.origins[0].line, 10);
  EXPECT_EQ(s.origins[1].line, 11);
  EXPECT_EQ(s.origins[2].line, 15);
  EXPECT_EQ(s.origins[2].file, "p.nff");
}

TEST(NffSemantics, CommentsAndLayout) {
  const Scene s = parse_nff(
      "# a comment\r\nb 0 0 1#no space\r\nv\r\n from 0 0 5 # eye\n\tat 0 0 0\nup 0 1 0\n"
      "angle 45 hither 1 resolution 2 2\nf 1 1 1 1 0 0 0 0 s 0 0 0 +1e0",
      "x.nff");
  EXPECT_EQ(s.background, Vec3(0, 0, 1));
  EXPECT_EQ(s.primitives.size(), 1u);
  EXPECT_EQ(s.origins[0].line, 8);
}

TEST(NffPolygons, ConcavePolygonsAndPatchesBecomeConvexPieces) {
  // An L shape as `p` and as `pp` (normals ignored), then a convex quad: primitives in order.
  const Scene s = parse_nff(
      kHeader +
          "p 6\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n"
          "pp 6\n0 0 1 0 0 1\n2 0 1 0 0 1\n2 1 1 0 0 1\n1 1 1 0 0 1\n1 2 1 0 0 1\n0 2 1 0 0 1\n"
          "p 4\n0 0 2\n1 0 2\n1 1 2\n0 1 2\n",
      "l.nff");
  ASSERT_EQ(s.primitives.size(), 5u);
  EXPECT_EQ(s.primitives[0].pieces, 2);
  EXPECT_EQ(s.primitives[0].outline.size(), 6u);
  EXPECT_EQ(s.primitives[1].piece, 1);
  EXPECT_EQ(s.primitives[2].pieces, 2);
  EXPECT_EQ(s.primitives[4].pieces, 1);
  for (int i : {0, 1}) EXPECT_EQ(s.origins[size_t(i)].line, 10);
  for (int i : {2, 3}) EXPECT_EQ(s.origins[size_t(i)].line, 17);
  EXPECT_EQ(s.origins[4].line, 24);
  EXPECT_TRUE(s.skipped.empty());
}

TEST(NffSpd, GearsAndTeapotLoad) {
  const Scene gears = load_scene(kSpdDir + "/gears-1.nff");
  // 145 rectangles and two 144-corner gear faces of 37 convex pieces each.
  EXPECT_EQ(gears.primitives.size(), 145u + 2 * 37);
  EXPECT_TRUE(gears.skipped.empty());
  const Scene teapot = load_scene(kSpdDir + "/teapot-1.nff");
  ASSERT_EQ(teapot.skipped.size(), 2u);
  // Eight patches on the lid's rim have normals on both sides of the face, twelve in the plane
  // y = 0 normals in their plane: shaded flat.
  EXPECT_EQ(teapot.skipped[0].kind, "'pp' vertex normal");
  EXPECT_EQ(teapot.skipped[0].reason, kFlatNormalsReason);
  EXPECT_EQ(teapot.skipped[0].count, 20);
  EXPECT_EQ(teapot.skipped[0].lines, (std::vector<int>{19, 23, 27, 31, 35}));
  EXPECT_EQ(teapot.skipped[1].kind, "degenerate 'pp'");
  EXPECT_EQ(teapot.skipped[1].reason, "polygon has zero area");
  EXPECT_EQ(teapot.skipped[1].count, 4);
  EXPECT_EQ(teapot.skipped[1].lines, (std::vector<int>{163, 167, 171, 175}));
  EXPECT_EQ(teapot.primitives.size(), 1u + 56 - 4);
  size_t smooth = 0;
  for (const Primitive& p : teapot.primitives) smooth += !p.normals.empty();
  EXPECT_EQ(smooth, 56u - 4 - 20);
  try {
    load_scene(kSpdDir + "/teapot-1.nff", {/*strict=*/true, false});
    ADD_FAILURE() << "strict reading accepted a degenerate patch";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line(), 163);
    EXPECT_NE(std::string(e.what()).find("pp: polygon has zero area (--strict)"), std::string::npos)
        << e.what();
  }
}

TEST(NffSkipped, DegenerateShapesAreSkippedAndCounted) {
  const int n = kHeaderLines + 1;
  const std::string text = kHeader +
                           "s 0 0 0 0\n"                 // zero radius
                           "c 0 0 0 1 0 0 0 1\n"         // zero length
                           "c 0 0 0 0 0 1 0 0\n"         // both radii zero
                           "p 3\n0 0 0\n1 0 0\n2 0 0\n"  // collinear
                           "p 3\n0 0 0\n1 0 0\n2 0 0\n"
                           "p 4\n1 1 1\n1 1 1\n1 1 1\n1 1 1\n"  // one point
                           "s 0 0 0 1\n";
  const Scene s = parse_nff(text, "d.nff");
  ASSERT_EQ(s.primitives.size(), 1u);
  EXPECT_EQ(s.origins[0].line, n + 16);
  ASSERT_EQ(s.skipped.size(), 3u);
  const SkippedRecords& sphere = s.skipped[0];
  EXPECT_EQ(sphere.kind, "degenerate 's'");
  EXPECT_EQ(sphere.reason, "sphere radius is zero");
  EXPECT_EQ(sphere.lines, std::vector<int>{n});
  EXPECT_EQ(s.skipped[1].kind, "degenerate 'c'");
  EXPECT_EQ(s.skipped[1].reason, "cone base and apex coincide");
  EXPECT_EQ(s.skipped[1].count, 2);  // one entry per record kind; the first one's reason
  EXPECT_EQ(s.skipped[1].lines, (std::vector<int>{n + 1, n + 2}));
  EXPECT_EQ(s.skipped[2].kind, "degenerate 'p'");
  EXPECT_EQ(s.skipped[2].count, 3);
  EXPECT_EQ(s.skipped[2].lines, (std::vector<int>{n + 3, n + 7, n + 11}));
  const std::vector<std::string> w = skipped_warnings(s, "d.nff");
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[1], "d.nff:" + std::to_string(n + 1) +
                      ": skipped 2 degenerate 'c' records (cone base and apex coincide; lines " +
                      std::to_string(n + 1) + ", " + std::to_string(n + 2) + ")");
  // Strict: the first one is an error at its line.
  for (const auto& [record, reason] : std::vector<std::pair<std::string, std::string>>{
           {"s 0 0 0 0\n", "sphere radius is zero"},
           {"c 0 0 0 1 0 0 0 1\n", "cone base and apex coincide"},
           {"c 0 0 0 0 0 1 0 0\n", "cone radii are both zero"},
           {"p 3\n0 0 0\n1 0 0\n2 0 0\n", "polygon has zero area"}}) {
    try {
      parse_nff(kHeader + record, "d.nff", {true, false});
      ADD_FAILURE() << record;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.line(), n);
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  }
}

TEST(NffSkipped, FirstFewLinesAndTheCount) {
  std::string text = kHeader;
  for (int i = 0; i < 12; ++i) text += "s 0 0 0 0\n";
  const Scene s = parse_nff(text, "d.nff");
  ASSERT_EQ(s.skipped.size(), 1u);
  EXPECT_EQ(s.skipped[0].count, 12);
  EXPECT_EQ(s.skipped[0].lines.size(), kSkippedLinesKept);
  EXPECT_NE(skipped_warnings(s, "d.nff")[0].find("skipped 12 degenerate 's' records"),
            std::string::npos);
  EXPECT_NE(skipped_warnings(s, "d.nff")[0].find(", ...)"), std::string::npos);
}

/// Records other renderers add to NFF, one of each kind (what a reader meets in files from the
/// wild): a count header, area and spot lights, textures, an environment map, and a textured
/// polygon-like record whose vertex lines follow it.
const std::string kExtensions =
    "number 3\n"  // line 1: an object-count header, before the view
    "v\nfrom 0 0 10\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 64 48\n"
    "la 0 5 0 1 0 0 0 0 1 1 1 1\n"  // line 9: an area light
    "ls 0 5 5 0 -1 -1 30 1 1 1\n"   // line 10: a spotlight
    "l 5 5 5\n"
    "tex brick.ppm 4 4\n"  // line 12: a texture with a file name
    "f 1 0.5 0.25 0.6 0.3 20 0 1\n"
    "env sky.hdr\n"  // line 14: an environment map
    "s 0 0 0 1\n"
    "tpp 3 brick.ppm\n"  // line 16: a textured patch: 3 vertex lines follow
    "0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n0 1 0 0 0 1 0 1\n"
    "la 1 5 0 1 0 0 0 0 1 1 1 1\n"  // line 20: a second area light
    "p 3\n0 0 1\n1 0 1\n0 1 1\n"
    "tex marble.ppm 1 1 s 2 0 0 1\n";  // line 25: a record shares the texture's line

TEST(NffSkipped, UnknownRecordsAreErrorsWithAHint) {
  try {
    parse_nff(kExtensions, "x.nff");
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("unknown keyword 'number' (--skip-unknown"),
              std::string::npos)
        << e.what();
  }
}

TEST(NffSkipped, SkipUnknownSkipsEveryKindWithItsContinuationLines) {
  const Scene s = parse_nff(kExtensions, "x.nff", {false, /*skip_unknown=*/true});
  ASSERT_EQ(s.primitives.size(), 3u);
  EXPECT_EQ(s.primitives[0].kind, ShapeKind::Sphere);
  EXPECT_EQ(s.origins[0].line, 15);
  EXPECT_EQ(s.primitives[1].kind, ShapeKind::Polygon);
  EXPECT_EQ(s.origins[1].line, 21);
  EXPECT_EQ(s.primitives[2].p0, Vec3(2, 0, 0));
  EXPECT_EQ(s.lights.size(), 1u);
  ASSERT_EQ(s.skipped.size(), 6u);
  const std::vector<std::tuple<std::string, int, std::vector<int>>> want = {
      {"unknown 'number'", 1, {1}},   {"unknown 'la'", 2, {9, 20}}, {"unknown 'ls'", 1, {10}},
      {"unknown 'tex'", 2, {12, 25}}, {"unknown 'env'", 1, {14}},   {"unknown 'tpp'", 1, {16}}};
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(s.skipped[i].kind, std::get<0>(want[i]));
    EXPECT_EQ(s.skipped[i].count, std::get<1>(want[i]));
    EXPECT_EQ(s.skipped[i].lines, std::get<2>(want[i]));
  }
  // Known records keep their checks: a stray number is still an error.
  EXPECT_THROW(parse_nff(kHeader + "s 0 0 0 1 2\n", "x.nff", {false, true}), SceneError);
}

struct BadCase {
  std::string text;
  int line;
  const char* message;
};

void expect_error(const BadCase& c) {
  SCOPED_TRACE(c.text);
  try {
    parse_nff(c.text, "bad.nff");
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_EQ(e.file(), "bad.nff");
    EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("bad.nff:" + std::to_string(c.line) + ": ", 0), 0u)
        << e.what();
  }
}

/// n points round a circle, one a line: a convex polygon.
std::string many_corners(int n) {
  std::string s;
  for (int i = 0; i < n; ++i)
    s += std::to_string(std::cos(6.283 * i / n)) + " " + std::to_string(std::sin(6.283 * i / n)) +
         " 0\n";
  return s;
}

TEST(NffErrors, EveryErrorHasALineAndAMessage) {
  const std::string h = kHeader;
  const int n = kHeaderLines + 1;  // the first line after the header
  const BadCase cases[] = {
      {h + "q 1 2 3\n", n, "unknown keyword 'q' (--skip-unknown"},
      {h + "s 0 0 0 1 2\n", n, "unexpected number '2'"},
      {h + "s 0 0 0\n", n, "'s' record ends early"},
      {h + "s 0 0 0\ns 1 1 1 1\n", n, "'s' record has too few numbers"},
      {h + "s 0 0 zero 1\n", n, "'zero' is not a number"},
      {h + "s 0 0\n0x 1\n", n + 1, "'0x' is not a number"},
      {h + "s 0 0 nan 1\n", n, "'nan' is not finite"},
      {h + "s 0 0 inf 1\n", n, "'inf' is not finite"},
      {h + "s 0 0 1e999 1\n", n, "out of range"},
      {h + "p 2\n0 0 0\n1 0 0\n", n, "must be a whole number >= 3"},
      {h + "p 3.5\n", n, "must be a whole number >= 3"},
      {h + "p 3\n0 0 0\n1 0 0\n", n, "'p' record ends early"},
      {h + "p 4\n0 0 0\n1 0 0\n1 1 1\n0 1 0\n", n, "not coplanar"},
      {h + "p 4\n0 0 0\n1 1 0\n1 0 0\n0 1 0\n", n, "not simple: its edges cross"},
      {h + "p 4\n0 0 0\n2 2 0\n2 0 0\n0 1 0\n", n, "not simple: edges 1-2 and 3-4"},
      {h + "p 5\n0 0 0\n2 0 0\n2 2 0\n1 0 0\n0 2 0\n", n, "not simple"},
      {h + "\np 1025\n" + many_corners(1025), n + 1, "p: polygon has 1025 vertices, at most 1024"},
      {h + "pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0\ns 0 0 0 1\n", n,
       "'pp' record has too few numbers"},
      {h + "l 1 2 3 1\ns 0 0 0 1\n", n, "too few numbers"},
      {h + "l 1 2 3 1\n", n, "'l' record ends early"},
      {h + "l 1 2 3 1 1 -1\n", n, "light colour must be finite and non-negative"},
      {h + "b 0 -1 0\n", n, "background colour must be finite and non-negative"},
      {h + "f 1 1 1 -0.5 0 0 0 1\n", n, "diffuse coefficient must be a finite number >= 0"},
      {h + "f 1 1 1 0.5 0 0 -1 1\n", n, "transmission coefficient"},
      {h + "f 1 1 1 0.5 0 0 0\n", n, "'f' record ends early"},
      {"v from 0 0 1 at 0 0 0 up 0 1 0 angle 45 hither 0 resolution 4 4\ns 0 0 0 1\n", 2,
       "before any 'f'"},
      {"v from 0 0 1 at 0 0 0 up 0 1 0 angle 45 hither 0 resolution 4 4\n\np 3", 3,
       "before any 'f'"},
      {"f 1 1 1 1 0 0 0 0\ns 0 0 0 1\n", 3, "no view block"},
      {"", 1, "no view block"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\n", 1, "missing 'resolution'"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nl 1 1 1\n", 6,
       "expected 'hither', 'resolution', got 'l'"},
      {"v\nfrom 0 0 1\nfrom 0 0 1\n", 3, "'from' given twice"},
      {h + "v\n", n, "second view block"},
      {h + "at 0 0 0\n", n, "'at' outside the view block"},
      {"v\nfrom 0 0 1\nat 0 0 1\nup 0 1 0\nangle 45\nhither 1\nresolution 4 4\n", 3,
       "'at' is the same point as 'from' (line 2)"},
      {"v\nresolution 4 4\nat 0 0 1\nhither 1\nup 0 1 0\nangle 45\nfrom 0 0 1\n", 3,
       "same point as 'from' (line 7)"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 0 2\nangle 45\nhither 1\nresolution 4 4\n", 4,
       "parallel to the view"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 0 0\nangle 45\nhither 1\nresolution 4 4\n", 4,
       "up vector is zero"},
      {"v\nfrom 0 0 1e200\nat 0 0 0\nup 0 0 0\nangle 45\nhither 1\nresolution 4 4\n", 2,
       "'from' must be within"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 180\nhither 1\nresolution 4 4\n", 5,
       "angle must be in (0, 180)"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 0\nhither 1\nresolution 4 4\n", 5,
       "angle must be in (0, 180)"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 0 4\n", 7,
       "whole number >= 1"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 4\n\n2.5\n", 9,
       "whole number >= 1"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 100000 4\n", 7,
       "at most 16384"},
      {"v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nhither x\n", 6, "'x' is not a number"},
      {h + std::string("s 0 0 0 1\n\x01\xff\x00garbage", 20), n + 1,
       "unknown keyword '???garbage'"},
  };
  for (const BadCase& c : cases) expect_error(c);
}

TEST(NffErrors, LongGarbageTokensAreShortened) {
  try {
    parse_nff(std::string(5000, 'z'), "bad.nff");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u);
  }
}

/// Whatever the input, the parser returns a scene or throws SceneError: nothing else.
void expect_scene_or_error(const std::string& text) {
  try {
    const Scene s = parse_nff(text, "fuzz.nff");
    validate(s);
  } catch (const SceneError&) {
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected " << e.what() << " for:\n" << text;
  }
}

TEST(NffFuzz, TruncationsMutationsAndGarbage) {
  const std::string base = kHeader +
                           "b 0.1 0.2 0.3\nl 1 1 1 0.5 0.5 0.5\n"
                           "s 0 0 0 1\nc 0 0 0 1 0 1 0 0.5\np 3\n0 0 0\n1 0 0\n0 1 0\n"
                           "pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n";
  for (size_t i = 0; i <= base.size(); ++i) expect_scene_or_error(base.substr(0, i));

  std::mt19937 rng(12345);
  const std::string alphabet = "0123456789 .-+e\n#abcfhlnpsv\t\r";
  for (int k = 0; k < 3000; ++k) {
    std::string t = base;
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const size_t at = rng() % t.size();
      switch (rng() % 3) {
        case 0:
          t[at] = alphabet[rng() % alphabet.size()];
          break;
        case 1:
          t.erase(at, 1 + rng() % 5);
          break;
        default:
          t.insert(at, 1, char(rng() % 256));
          break;
      }
    }
    expect_scene_or_error(t);
  }
  for (int k = 0; k < 200; ++k) {
    std::string t(rng() % 400, '\0');
    for (char& c : t) c = char(rng() % 256);
    expect_scene_or_error(t);
  }
  expect_scene_or_error(kHeader + "p 2000000000\n1 2 3\n");
  expect_scene_or_error(kHeader + "p 1e300\n");
}

}  // namespace
}  // namespace rtm
