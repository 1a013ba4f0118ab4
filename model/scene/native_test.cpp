#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "scene/scene.h"

namespace rtm {
namespace {

/// A scene whose only primitive (line 6) is `prim`.
std::string with_primitive(const std::string& prim) {
  return "name: t\n"
         "camera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\n"
         "materials:\n"
         "  m: {color: [1, 0, 0]}\n"
         "primitives:\n"
         "  - " +
         prim + "\n";
}

const Primitive& only(const Scene& s) {
  EXPECT_EQ(s.primitives.size(), 1u);
  return s.primitives.at(0);
}

Primitive parse_one(const std::string& prim) {
  const Scene s = parse_native(with_primitive(prim), "one.yaml");
  return only(s);
}

void expect_same(const Primitive& a, const Primitive& b) {
  EXPECT_EQ(a.kind, b.kind);
  for (int i = 0; i < 10; ++i)
    EXPECT_NEAR(a.q.c[size_t(i)], b.q.c[size_t(i)], 1e-12) << "coefficient " << i;
  ASSERT_EQ(a.clips.size(), b.clips.size());
  for (size_t i = 0; i < a.clips.size(); ++i) {
    EXPECT_NEAR(length(a.clips[i].n - b.clips[i].n), 0, 1e-12);
    EXPECT_NEAR(a.clips[i].d, b.clips[i].d, 1e-12);
  }
  EXPECT_NEAR(length(a.bounds.lo - b.bounds.lo), 0, 1e-12);
  EXPECT_NEAR(length(a.bounds.hi - b.bounds.hi), 0, 1e-12);
}

TEST(NativeFormat, WholeSceneWithDefaultsAndValues) {
  const Scene s = parse_native(
      "name: demo\n"
      "camera: {eye: [0, 2, 10], look_at: [0, 0, 0], up: [0, 0, 1], fov: 30, resolution: [320, "
      "240]}\n"
      "background: [0.1, 0.2, 0.4]\n"
      "ambient: [0.2, 0.3, 0.4]\n"
      "lights:\n"
      "  - {position: [5, 10, 5], color: [0.6, 0.5, 0.4]}\n"
      "  - {position: [-5, 10, 5]}\n"
      "materials:\n"
      "  red: {color: [1, 0, 0], ambient: 0.15, diffuse: 0.8, specular: 0.2, transmission: 0.3, "
      "ior: 1.4}\n"
      "  plain: {}\n"
      "render: {threshold: 0.004, max_depth: 7, grid: [4, 5, 6], spawn_offset: 1e-6}\n"
      "primitives:\n"
      "  - {sphere: {center: [0, 1, 0], radius: 1}, material: plain}\n"
      "  - material: red\n"
      "    sphere:\n"
      "      center: [2, 1, 0]\n"
      "      radius: 0.5\n",
      "dir/demo-file.yaml");
  EXPECT_EQ(s.name, "demo");
  EXPECT_EQ(s.camera.eye, Vec3(0, 2, 10));
  EXPECT_EQ(s.camera.up, Vec3(0, 0, 1));
  EXPECT_EQ(s.camera.fov_deg, 30);
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 240);
  EXPECT_EQ(s.background, Vec3(0.1, 0.2, 0.4));
  EXPECT_EQ(s.ambient_light, Vec3(0.2, 0.3, 0.4));
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].color, Vec3(0.6, 0.5, 0.4));
  EXPECT_EQ(s.lights[1].color, Vec3(1, 1, 1));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "red");
  EXPECT_EQ(s.materials[0].ambient, 0.15);
  EXPECT_EQ(s.materials[0].diffuse, 0.8);
  EXPECT_EQ(s.materials[0].specular, 0.2);
  EXPECT_EQ(s.materials[0].transmission, 0.3);
  EXPECT_EQ(s.materials[0].ior, 1.4);
  const Material def;
  EXPECT_EQ(s.materials[1].color, def.color);
  EXPECT_EQ(s.materials[1].ambient, def.ambient);
  EXPECT_EQ(s.materials[1].diffuse, def.diffuse);
  EXPECT_EQ(s.materials[1].ior, def.ior);
  EXPECT_EQ(s.threshold, 0.004);
  EXPECT_EQ(s.max_depth, 7);
  EXPECT_EQ(s.spawn_offset, 1e-6);
  EXPECT_EQ(s.grid.resolution, (std::array<int, 3>{4, 5, 6}));
  ASSERT_EQ(s.primitives.size(), 2u);
  EXPECT_EQ(s.primitives[0].material, 1);
  EXPECT_EQ(s.primitives[1].material, 0);
  EXPECT_EQ(s.primitives[1].p0, Vec3(2, 1, 0));
  EXPECT_EQ(s.origins[0].line, 13);
  EXPECT_EQ(s.origins[1].line, 14);
  EXPECT_EQ(s.origins[1].file, "dir/demo-file.yaml");
}

TEST(NativeFormat, MinimalSceneDefaults) {
  const Scene s = parse_native("camera: {eye: [0, 0, 5], look_at: [0, 0, 0]}\nprimitives: []\n",
                               "dir/minimal.yml");
  const Scene d;
  EXPECT_EQ(s.name, "minimal");
  EXPECT_EQ(s.camera.up, d.camera.up);
  EXPECT_EQ(s.camera.fov_deg, d.camera.fov_deg);
  EXPECT_EQ(s.camera.width, d.camera.width);
  EXPECT_EQ(s.background, d.background);
  EXPECT_EQ(s.ambient_light, d.ambient_light);
  EXPECT_EQ(s.threshold, d.threshold);
  EXPECT_EQ(s.max_depth, d.max_depth);
  EXPECT_EQ(s.spawn_offset, d.spawn_offset);
  EXPECT_EQ(s.grid.resolution, (std::array<int, 3>{0, 0, 0}));
  EXPECT_TRUE(s.primitives.empty());
  EXPECT_EQ(
      parse_native(
          "camera: {eye: [0, 0, 5], look_at: [0, 0, 0]}\nrender: {grid: auto}\nprimitives: []\n",
          "a.yaml")
          .grid.resolution,
      (std::array<int, 3>{0, 0, 0}));
}

TEST(NativeShapes, Sphere) {
  const Primitive p = parse_one("{sphere: {center: [1, 2, 3], radius: 0.5}, material: m}");
  expect_same(p, make_sphere({1, 2, 3}, 0.5));
}

TEST(NativeShapes, EllipsoidDefaultFrameIsTheWorldFrame) {
  const Primitive p = parse_one("{ellipsoid: {center: [1, 2, 3], radii: [3, 2, 1]}, material: m}");
  expect_same(p, make_ellipsoid(Frame{{1, 2, 3}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {3, 2, 1}));
  EXPECT_NEAR(p.q.value({4, 2, 3}), 0, 1e-12);  // radius 3 along world x
  EXPECT_NEAR(p.q.value({1, 4, 3}), 0, 1e-12);
  EXPECT_NEAR(p.q.value({1, 2, 4}), 0, 1e-12);
}

TEST(NativeShapes, EllipsoidAxisAndXAxis) {
  // x_axis is orthogonalised against axis: [1, 1, 0] becomes world x.
  const Primitive p = parse_one(
      "{ellipsoid: {center: [0, 0, 0], radii: [3, 2, 1], axis: [0, 2, 0], x_axis: [1, 1, 0]}, "
      "material: m}");
  expect_same(p, make_ellipsoid(Frame{{0, 0, 0}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {3, 2, 1}));
  EXPECT_NEAR(p.q.value({3, 0, 0}), 0, 1e-12);
  EXPECT_NEAR(p.q.value({0, 0, 2}), 0, 1e-12);
  EXPECT_NEAR(p.q.value({0, 1, 0}), 0, 1e-12);
}

TEST(NativeShapes, CylinderAndCone) {
  expect_same(parse_one("{cylinder: {base: [0, 0, 0], apex: [0, 3, 0], radius: 0.5}, material: m}"),
              make_cone({0, 0, 0}, 0.5, {0, 3, 0}, 0.5));
  const Primitive c = parse_one(
      "{cone: {base: [1, 0, 0], base_radius: 1, apex: [1, 0, 2], apex_radius: 0}, material: m}");
  expect_same(c, make_cone({1, 0, 0}, 1, {1, 0, 2}, 0));
  EXPECT_EQ(c.kind, ShapeKind::Cone);
}

TEST(NativeShapes, Paraboloid) {
  const Primitive p =
      parse_one("{paraboloid: {vertex: [0, 1, 0], axis: [0, 1, 0], k: 2, height: 3}, material: m}");
  EXPECT_EQ(p.kind, ShapeKind::Paraboloid);
  EXPECT_NEAR(p.q.value({0, 1, 0}), 0, 1e-12);               // the vertex
  EXPECT_NEAR(p.q.value({std::sqrt(6.0), 4, 0}), 0, 1e-12);  // the rim: r² = k h
  EXPECT_TRUE(p.inside_clips({0, 2, 0}));
  EXPECT_FALSE(p.inside_clips({0, 4.5, 0}));
  // The axis defaults to z.
  const Primitive z = parse_one("{paraboloid: {vertex: [0, 0, 0], k: 1, height: 1}, material: m}");
  EXPECT_NEAR(z.q.value({1, 0, 1}), 0, 1e-12);
}

TEST(NativeShapes, Hyperboloids) {
  const Primitive one = parse_one(
      "{hyperboloid: {center: [0, 0, 0], axis: [0, 0, 1], a: 1, c: 2, half_height: 3}, material: "
      "m}");
  expect_same(one, make_hyperboloid1(Frame{}, 1, 2, 3));
  const Primitive two = parse_one(
      "{hyperboloid: {center: [0, 0, 0], a: 1, c: 2, half_height: 3, sheets: 2}, material: m}");
  expect_same(two, make_hyperboloid2(Frame{}, 1, 2, 3));
  EXPECT_EQ(two.kind, ShapeKind::Hyperboloid2);
  const Primitive y = parse_one(
      "{hyperboloid: {center: [0, 1, 0], axis: [0, 1, 0], a: 1, c: 1, half_height: 2, sheets: 1}, "
      "material: m}");
  EXPECT_NEAR(y.q.value({1, 1, 0}), 0, 1e-12);  // the waist, around the y axis
  EXPECT_NEAR(y.q.value({0, 1, 1}), 0, 1e-12);
}

TEST(NativeShapes, PlanePolygonQuadric) {
  const Primitive pl = parse_one(
      "{plane: {normal: [0, 2, 0], d: -1, box: {min: [-1, 0, -1], max: [1, 1, 1]}}, material: m}");
  expect_same(pl, make_plane({0, 2, 0}, -1, Aabb{{-1, 0, -1}, {1, 1, 1}}));
  const Primitive pd = parse_one(
      "{plane: {normal: [0, 1, 0], box: {min: [-1, -1, -1], max: [1, 1, 1]}}, material: m}");
  EXPECT_EQ(pd.q.c[kJ], 0);  // d defaults to 0
  const Primitive po =
      parse_one("{polygon: {vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]}, material: m}");
  expect_same(po, make_polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
  EXPECT_EQ(po.vertices.size(), 4u);
  const Primitive q = parse_one(
      "{quadric: {coefficients: [1, 0, -1, 0, 0, 0, 0, -2, 0, 0], box: {min: [-1, -1, -1], max: "
      "[1, 1, 1]},"
      " clip: [[1, 0, 0, -0.5], [0, 0, 1, 0]]}, material: m}");
  expect_same(q, make_raw_quadric({1, 0, -1, 0, 0, 0, 0, -2, 0, 0}, Aabb{{-1, -1, -1}, {1, 1, 1}},
                                  {{{1, 0, 0}, -0.5}, {{0, 0, 1}, 0}}));
  EXPECT_EQ(q.kind, ShapeKind::Raw);
}

TEST(NativeShapes, ConcavePolygonBecomesConvexPieces) {
  const Scene s = parse_native(
      "camera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\nmaterials: {m: {}}\nprimitives:\n"
      "  - {polygon: {vertices: [[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, "
      "0]]}, material: m}\n"
      "  - {sphere: {center: [5, 0, 0], radius: 1}, material: m}\n",
      "l.yaml");
  ASSERT_EQ(s.primitives.size(), 3u);  // the L shape's two pieces, then the sphere
  EXPECT_EQ(s.primitives[0].pieces, 2);
  EXPECT_EQ(s.primitives[1].piece, 1);
  EXPECT_EQ(s.primitives[0].outline.size(), 6u);
  EXPECT_EQ(s.origins[1].line, 4);
  EXPECT_EQ(s.primitives[2].kind, ShapeKind::Sphere);
}

struct BadCase {
  std::string text;
  int line;
  const char* message;
};

void expect_error(const BadCase& c) {
  SCOPED_TRACE(c.text);
  try {
    parse_native(c.text, "bad.yaml");
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_EQ(e.file(), "bad.yaml");
    EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
  }
}

const std::string kCam = "camera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\n";
const std::string kPrims = "primitives: []\n";

TEST(NativeErrors, SyntaxAndStructure) {
  const BadCase cases[] = {
      {"camera: {eye: [0, 0\n", 2, "YAML syntax error"},
      {"a: b\n\tc: d\n", 2, "YAML syntax error"},
      {"camera: [\n", 2, "YAML syntax error"},
      {"", 1, "expected a mapping"},
      {"- 1\n- 2\n", 1, "expected a mapping"},
      {"42\n", 1, "expected a mapping"},
      {kCam + kPrims + "camrea: {}\n", 3, "unknown key 'camrea'"},
      {kPrims, 1, "missing required key 'camera'"},
      {kCam, 1, "missing required key 'primitives'"},
      {kCam + kPrims + "camera: {}\n", 3, "duplicate key 'camera'"},
      {kCam + kPrims + "[1]: 2\n", 3, "keys must be plain names"},
      {kCam + "primitives: {}\n", 2, "expected a list of primitives"},
      {kCam + kPrims + "name: [a]\n", 3, "name: expected a string"},
      {kCam + kPrims + "name: ../x\n", 3, "name: must be 1 to 100 letters"},
      {kCam + kPrims + "name: a b\n", 3, "name: must be 1 to 100 letters"},
      {kCam + kPrims + "name: ''\n", 3, "name: must be 1 to 100 letters"},
      // An alias repeats a subtree for a few bytes: refused, anchors alone are harmless.
      {"camera: {eye: &e [0, 0, 10], look_at: [0, 0, 0]}\nprimitives: []\nambient: *e\n", 3,
       "YAML aliases (*name) are not supported"},
      {"materials: {m: {}}\ncamera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\nprimitives:\n"
       "  - &p {sphere: {center: [0, 0, 0], radius: 1}, material: m}\n  - *p\n",
       5, "YAML aliases"},
  };
  for (const BadCase& c : cases) expect_error(c);
}

TEST(NativeErrors, CameraAndNumbers) {
  const auto cam = [](const std::string& c) { return "name: x\ncamera: " + c + "\n" + kPrims; };
  const BadCase cases[] = {
      {cam("[0, 0, 1]"), 2, "camera: expected a mapping"},
      {cam("{look_at: [0, 0, 0]}"), 2, "missing required key 'eye'"},
      {cam("{eye: [0, 0, 1]}"), 2, "missing required key 'look_at'"},
      {cam("{eye: [0, 0], look_at: [0, 0, 0]}"), 2, "camera.eye: expected [x, y, z] (3 numbers)"},
      {cam("{eye: [0, 0, 1, 2], look_at: [0, 0, 0]}"), 2, "expected [x, y, z]"},
      {cam("{eye: 5, look_at: [0, 0, 0]}"), 2, "expected [x, y, z]"},
      {cam("{eye: [a, 0, 1], look_at: [0, 0, 0]}"), 2, "camera.eye[0]: expected a number, got 'a'"},
      {cam("{eye: [[1], 0, 1], look_at: [0, 0, 0]}"), 2, "camera.eye[0]: expected a number"},
      {cam("{eye: [.nan, 0, 1], look_at: [0, 0, 0]}"), 2, "is not finite"},
      {cam("{eye: [.inf, 0, 1], look_at: [0, 0, 0]}"), 2, "is not finite"},
      {cam("{eye: [-.INF, 0, 1], look_at: [0, 0, 0]}"), 2, "is not finite"},
      {cam("{eye: [nan, 0, 1], look_at: [0, 0, 0]}"), 2, "is not finite"},
      {cam("{eye: [1e999, 0, 1], look_at: [0, 0, 0]}"), 2, "out of range"},
      {cam("{eye: [0x10, 0, 1], look_at: [0, 0, 0]}"), 2, "expected a number, got '0x10'"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 0], fov: 180}"), 2, "camera.fov: must be in (0, 180)"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 0], fov: -5}"), 2, "must be in (0, 180)"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 0], resolution: [0, 10]}"), 2,
       "resolution[0]: must be >= 1"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 0], resolution: [10, 2.5]}"), 2,
       "expected a whole number"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 0], resolution: [20000, 10]}"), 2, "at most 16384"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 0], resolution: 10}"), 2, "expected [width, height]"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 1]}"), 2, "eye and look_at coincide"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 0], up: [0, 0, 3]}"), 2,
       "parallel to the view direction"},
      {cam("{eye: [0, 0, 1], look_at: [0, 0, 0], fovv: 30}"), 2,
       "unknown key 'fovv' (allowed: eye, look_at"},
      {cam("\n  eye: [0, 0, 1]\n  look_at: [0, 0, 0]\n  fov: abc"), 5,
       "camera.fov: expected a number"},
  };
  for (const BadCase& c : cases) expect_error(c);
}

TEST(NativeErrors, LightsMaterialsRender) {
  const BadCase cases[] = {
      {kCam + kPrims + "background: [0, -1, 0]\n", 3, "background: colour components must be >= 0"},
      {kCam + kPrims + "ambient: [0, 0]\n", 3, "ambient: expected [r, g, b]"},
      {kCam + kPrims + "lights: {position: [0, 0, 0]}\n", 3, "lights: expected a list"},
      {kCam + kPrims + "lights:\n  - {color: [1, 1, 1]}\n", 4,
       "lights[0]: missing required key 'position'"},
      {kCam + kPrims + "lights:\n  - {position: [0, 0, 0], colour: [1, 1, 1]}\n", 4,
       "unknown key 'colour'"},
      {kCam + kPrims + "lights:\n  - {position: [0, 0, 0], color: [1, -1, 1]}\n", 4,
       "must be >= 0"},
      {kCam + kPrims + "materials: [a, b]\n", 3, "materials: expected a mapping"},
      {kCam + kPrims + "materials:\n  a: 5\n", 4, "materials.a: expected a mapping"},
      {kCam + kPrims + "materials:\n  a: {ior: 0}\n", 4, "materials.a.ior: must be > 0"},
      {kCam + kPrims + "materials:\n  a: {diffuse: -0.1}\n", 4,
       "materials.a.diffuse: must be >= 0"},
      {kCam + kPrims + "materials:\n  a: {ambient: -1}\n", 4, "must be >= 0"},
      {kCam + kPrims + "materials:\n  a: {specular: -1}\n", 4, "must be >= 0"},
      {kCam + kPrims + "materials:\n  a: {transmission: -1}\n", 4, "must be >= 0"},
      {kCam + kPrims + "materials:\n  a: {color: [2, 2]}\n", 4, "expected [r, g, b]"},
      {kCam + kPrims + "materials:\n  a: {difuse: 1}\n", 4, "unknown key 'difuse'"},
      {kCam + kPrims + "materials:\n  a: {}\n  a: {}\n", 5, "duplicate material 'a'"},
      {kCam + kPrims + "materials:\n  [x]: {}\n", 4, "material names must be plain strings"},
      {kCam + kPrims + "render: {threshold: 1}\n", 3, "render.threshold: must be in [0, 1)"},
      {kCam + kPrims + "render: {threshold: -0.1}\n", 3, "must be in [0, 1)"},
      {kCam + kPrims + "render: {max_depth: 0}\n", 3, "render.max_depth: must be >= 1"},
      {kCam + kPrims + "render: {spawn_offset: -1}\n", 3, "render.spawn_offset: must be >= 0"},
      {kCam + kPrims + "render: {grid: [1, 2]}\n", 3, "expected 'auto' or [nx, ny, nz]"},
      {kCam + kPrims + "render: {grid: fine}\n", 3, "expected 'auto' or [nx, ny, nz]"},
      {kCam + kPrims + "render: {grid: [0, 1, 1]}\n", 3, "render.grid[0]: must be >= 1"},
      {kCam + kPrims + "render: {grid: [1000, 1000, 1000]}\n", 3, "too many voxels"},
      {kCam + kPrims + "render: {depth: 3}\n", 3, "unknown key 'depth'"},
      // The hit refinement is a machine key now.
      {kCam + kPrims + "render: {refine_hits: false}\n", 3,
       "render.refine_hits: not a scene setting: the machine key hit_refine (none or newton) "
       "chooses it"},
  };
  for (const BadCase& c : cases) expect_error(c);
}

TEST(NativeErrors, Primitives) {
  const auto p = [](const std::string& prim) { return BadCase{with_primitive(prim), 6, ""}; };
  const std::pair<std::string, const char*> cases[] = {
      {"5", "primitives[0]: expected a mapping"},
      {"{sphere: {center: [0, 0, 0], radius: 1}}", "missing required key 'material'"},
      {"{material: m}", "expected exactly one shape"},
      {"{sphere: {center: [0, 0, 0], radius: 1}, cone: {}, material: m}",
       "expected exactly one shape"},
      {"{sphear: {center: [0, 0, 0], radius: 1}, material: m}", "unknown key 'sphear'"},
      {"{sphere: {center: [0, 0, 0], radius: 1}, material: n}", "unknown material 'n'"},
      {"{sphere: {center: [0, 0, 0], radius: 1}, material: [m]}", "material: expected a string"},
      {"{sphere: {center: [0, 0, 0], radius: 0}, material: m}",
       "primitives[0].sphere.radius: must be > 0"},
      {"{sphere: {center: [0, 0, 0]}, material: m}",
       "primitives[0].sphere: missing required key 'radius'"},
      {"{sphere: {centre: [0, 0, 0], radius: 1}, material: m}", "unknown key 'centre'"},
      {"{sphere: [0, 0, 0, 1], material: m}", "primitives[0].sphere: expected a mapping"},
      {"{ellipsoid: {center: [0, 0, 0], radii: [1, -1, 1]}, material: m}", "radii must all be > 0"},
      {"{ellipsoid: {center: [0, 0, 0], radii: [1, 1, 1], axis: [0, 0, 0]}, material: m}",
       "ellipsoid.axis: must be a non-zero finite vector"},
      {"{ellipsoid: {center: [0, 0, 0], radii: [1, 1, 1], axis: [0, 1, 0], x_axis: [0, -2, 0]}, "
       "material: m}",
       "x_axis: must not be parallel to axis"},
      {"{cylinder: {base: [0, 0, 0], apex: [0, 1, 0], radius: -1}, material: m}",
       "cylinder.radius: must be > 0"},
      {"{cylinder: {base: [0, 0, 0], apex: [0, 0, 0], radius: 1}, material: m}",
       "cone base and apex coincide"},
      {"{cone: {base: [0, 0, 0], base_radius: 0, apex: [0, 1, 0], apex_radius: 0}, material: m}",
       "cone radii are both zero"},
      {"{cone: {base: [0, 0, 0], base_radius: -1, apex: [0, 1, 0], apex_radius: 0}, material: m}",
       "cone.base_radius: must be >= 0"},
      {"{paraboloid: {vertex: [0, 0, 0], k: 0, height: 1}, material: m}",
       "paraboloid.k: must be > 0"},
      {"{paraboloid: {vertex: [0, 0, 0], k: 1}, material: m}", "missing required key 'height'"},
      {"{hyperboloid: {center: [0, 0, 0], a: 1, c: 1, half_height: 1, sheets: 3}, material: m}",
       "must be 1 or 2"},
      {"{hyperboloid: {center: [0, 0, 0], a: 1, c: 1, half_height: 1, sheets: 0}, material: m}",
       "must be >= 1"},
      {"{hyperboloid: {center: [0, 0, 0], a: 1, c: 2, half_height: 1, sheets: 2}, material: m}",
       "half height must exceed c"},
      {"{hyperboloid: {center: [0, 0, 0], a: 1, c: 1, height: 1}, material: m}",
       "unknown key 'height'"},
      {"{plane: {normal: [0, 0, 0], box: {min: [0, 0, 0], max: [1, 1, 1]}}, material: m}",
       "plane.normal: must be a non-zero finite vector"},
      {"{plane: {normal: [0, 1, 0], box: {min: [0, 2, 0], max: [1, 1, 1]}}, material: m}",
       "plane.box: min must not exceed max"},
      {"{plane: {normal: [0, 1, 0], box: {min: [0, 0, 0]}}, material: m}",
       "plane.box: missing required key 'max'"},
      {"{plane: {normal: [0, 1, 0]}, material: m}", "missing required key 'box'"},
      {"{polygon: {vertices: [[0, 0, 0], [1, 0, 0]]}, material: m}",
       "at least 3 [x, y, z] vertices"},
      {"{polygon: {vertices: [[0, 0, 0], [1, 0, 0], [0, 1]]}, material: m}",
       "polygon.vertices[2]: expected [x, y, z]"},
      {"{polygon: {vertices: [[0, 0, 0], [2, 2, 0], [2, 0, 0], [0, 1, 0]]}, material: m}",
       "not simple"},
      {"{polygon: {vertices: [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}, material: m}", "zero area"},
      {"{quadric: {coefficients: [1, 1, 1, 0, 0, 0, 0, 0, 0], box: {min: [0, 0, 0], max: [1, 1, "
       "1]}}, material: m}",
       "quadric.coefficients: expected [A, B, C, D, E, F, G, H, I, J] (10 numbers)"},
      {"{quadric: {coefficients: [0, 0, 0, 0, 0, 0, 0, 0, 0, 1], box: {min: [0, 0, 0], max: [1, 1, "
       "1]}}, material: m}",
       "quadric is degenerate"},
      {"{quadric: {coefficients: [1, 1, 1, 0, 0, 0, 0, 0, 0, -1]}, material: m}",
       "missing required key 'box'"},
      {"{quadric: {coefficients: [1, 1, 1, 0, 0, 0, 0, 0, 0, -1], box: {min: [0, 0, 0], max: [1, "
       "1, 1]},"
       " clip: [[1, 0, 0]]}, material: m}",
       "quadric.clip[0]: expected [nx, ny, nz, d] (4 numbers)"},
      {"{quadric: {coefficients: [1, 1, 1, 0, 0, 0, 0, 0, 0, -1], box: {min: [0, 0, 0], max: [1, "
       "1, 1]},"
       " clip: [[0, 0, 0, 1]]}, material: m}",
       "half-space normal must not be zero"},
      {"{quadric: {coefficients: [1, 1, 1, 0, 0, 0, 0, 0, 0, -1], box: {min: [0, 0, 0], max: [1, "
       "1, 1]},"
       " clip: 3}, material: m}",
       "quadric.clip: expected a list"},
  };
  for (const auto& [prim, message] : cases) {
    BadCase c = p(prim);
    c.message = message;
    expect_error(c);
  }
  std::string circle;  // 1025 corners: one past the most a polygon may have
  for (int i = 0; i < 1025; ++i)
    circle += (i ? ", [" : "[") + std::to_string(std::cos(6.283 * i / 1025)) + ", " +
              std::to_string(std::sin(6.283 * i / 1025)) + ", 0]";
  expect_error({with_primitive("{polygon: {vertices: [" + circle + "]}, material: m}"), 6,
                "primitives[0].polygon: polygon has 1025 vertices, at most 1024"});
  // A block-style primitive reports the line of the offending value.
  expect_error(
      {with_primitive("material: m\n    sphere:\n      center: [0, 0, 0]\n      radius: -2"), 9,
       "sphere.radius: must be > 0"});
}

/// Whatever the input, the parser returns a scene or throws SceneError: nothing else.
void expect_scene_or_error(const std::string& text) {
  try {
    const Scene s = parse_native(text, "fuzz.yaml");
    validate(s);
  } catch (const SceneError&) {
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected " << e.what() << " for:\n" << text;
  }
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(NativeFuzz, TruncationsMutationsAndGarbage) {
  const std::string base = read_file(RTM_SOURCE_DIR "/scenes/default.yaml");
  ASSERT_FALSE(base.empty());
  for (size_t i = 0; i <= base.size(); i += 7) expect_scene_or_error(base.substr(0, i));
  std::mt19937 rng(777);
  const std::string alphabet = "0123456789 .-+e\n#:,[]{}-&*!|>'\"\tabcxyz";
  for (int k = 0; k < 400; ++k) {
    std::string t = base;
    for (int e = 0; e < 3; ++e) {
      const size_t at = rng() % t.size();
      if (rng() % 2)
        t[at] = alphabet[rng() % alphabet.size()];
      else
        t.insert(at, 1, char(rng() % 256));
    }
    expect_scene_or_error(t);
  }
  for (int k = 0; k < 100; ++k) {
    std::string t(rng() % 300, '\0');
    for (char& c : t) c = char(rng() % 256);
    expect_scene_or_error(t);
  }
  expect_scene_or_error(std::string(20000, '[') + std::string(20000, ']'));  // deep nesting
  expect_scene_or_error("a: &x [*x]\n");
  expect_scene_or_error(
      kCam + "primitives:\n  - &p {sphere: {center: [0, 0, 0], radius: 1}, material: m}\n  - *p\n");
}

// ---- load_scene, default_scene, set_resolution, validate ----

class SceneFiles : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  void SetUp() override {
    dir_ = ::testing::TempDir() + "rtm_scene_test_" + std::to_string(::getpid());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string dir_;
};

TEST_F(SceneFiles, LoadsByExtension) {
  const std::string yaml = with_primitive("{sphere: {center: [0, 0, 0], radius: 1}, material: m}");
  EXPECT_EQ(load_scene(write("a.yaml", yaml)).primitives.size(), 1u);
  EXPECT_EQ(load_scene(write("b.YML", yaml)).name, "t");
  const Scene n =
      load_scene(write("c.nff",
                       "v from 0 0 1 at 0 0 0 up 0 1 0 angle 45 hither 0 resolution 4 4\n"
                       "f 1 1 1 1 0 0 0 0\ns 0 0 0 1\n"));
  EXPECT_EQ(n.name, "c");
  EXPECT_EQ(n.origins[0].file, dir_ + "/c.nff");
}

TEST_F(SceneFiles, ErrorsNameTheFile) {
  const auto expect = [](const std::string& path, int line, const char* message) {
    try {
      load_scene(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.line(), line);
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  expect(write("a.txt", "x"), 0, "unknown scene file extension '.txt'");
  expect(write("noext", "x"), 0, "unknown scene file extension ''");
  expect(dir_ + "/missing.yaml", 0, "cannot read scene file");
  std::filesystem::create_directories(dir_ + "/d.nff");
  expect(dir_ + "/d.nff", 0, "cannot read scene file");
  expect(write("bad.nff", "v\nfrom 0 0 1\nq"), 3, "expected 'at'");
  expect(write("bad.yaml", kCam + "primitives: [\n"), 3, "YAML syntax error");
}

TEST(SceneDefault, HasEveryKindAndLooksAfterItself) {
  const Scene s = default_scene();
  EXPECT_EQ(s.name, "default");
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 240);
  EXPECT_NO_THROW(validate(s));
  std::set<ShapeKind> kinds;
  for (const Primitive& p : s.primitives) kinds.insert(p.kind);
  for (ShapeKind k : {ShapeKind::Sphere, ShapeKind::Ellipsoid, ShapeKind::Cylinder, ShapeKind::Cone,
                      ShapeKind::Paraboloid, ShapeKind::Hyperboloid1, ShapeKind::Hyperboloid2,
                      ShapeKind::Plane, ShapeKind::Polygon, ShapeKind::Raw})
    EXPECT_TRUE(kinds.count(k)) << "missing " << shape_name(k);
  EXPECT_LT(s.primitives.size(), 100u);
  ASSERT_GE(s.lights.size(), 2u);
  EXPECT_NE(s.lights[0].color, s.lights[1].color);
  bool glass = false, mirror = false, diffuse = false;
  for (const Material& m : s.materials) {
    glass = glass || (m.transmission > 0.5 && m.ior == 1.5);
    mirror = mirror || m.specular >= 0.5;
    diffuse = diffuse || (m.diffuse >= 0.5 && m.specular == 0 && m.transmission == 0);
  }
  EXPECT_TRUE(glass && mirror && diffuse);
  EXPECT_NE(s.background, Vec3(0, 0, 0));
  ASSERT_EQ(s.origins.size(), s.primitives.size());
  EXPECT_EQ(s.origins[0].file, "<built-in default scene>");
  // The embedded copy is the file in the tree (CMake re-embeds it when the file changes).
  const Scene f = load_scene(RTM_SOURCE_DIR "/scenes/default.yaml");
  ASSERT_EQ(f.primitives.size(), s.primitives.size());
  for (size_t i = 0; i < f.primitives.size(); ++i)
    EXPECT_EQ(f.primitives[i].q.c, s.primitives[i].q.c);
}

TEST(SceneResolution, KeepsTheHorizontalFieldOfView) {
  Scene s = default_scene();
  set_resolution(s, 64, 16);
  EXPECT_EQ(s.camera.width, 64);
  EXPECT_EQ(s.camera.height, 16);
  EXPECT_EQ(s.camera.fov_deg, 50);
  EXPECT_THROW(set_resolution(s, 0, 16), std::invalid_argument);
  EXPECT_THROW(set_resolution(s, 16, -1), std::invalid_argument);
  EXPECT_THROW(set_resolution(s, 100000, 16), std::invalid_argument);
  EXPECT_EQ(s.camera.width, 64);
}

TEST(SceneValidate, RejectsEveryBrokenPart) {
  const Scene good = default_scene();
  const auto expect = [&](const std::function<void(Scene&)>& breakit, const char* message) {
    Scene s = good;
    breakit(s);
    try {
      validate(s);
      ADD_FAILURE() << "no error for " << message;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  const double nan = std::nan("");
  expect([&](Scene& s) { s.camera.eye.x = nan; }, "camera eye is not finite");
  expect([](Scene& s) { s.camera.look_at = s.camera.eye; }, "eye and look_at coincide");
  expect([](Scene& s) { s.camera.up = s.camera.look_at - s.camera.eye; }, "parallel");
  expect([](Scene& s) { s.camera.fov_deg = 0; }, "field of view");
  expect([](Scene& s) { s.camera.height = 0; }, "resolution must be at least 1x1");
  expect([](Scene& s) { s.background.y = -1; }, "background");
  expect([&](Scene& s) { s.ambient_light.y = nan; }, "ambient light");
  expect([&](Scene& s) { s.lights[1].position.z = nan; }, "light 1: light position is not finite");
  expect([](Scene& s) { s.lights[0].color.z = -1; }, "light 0: light colour");
  expect([](Scene& s) { s.materials[2].ior = 0; }, "material 'mirror': index of refraction");
  expect([](Scene& s) { s.materials[0].specular = -1; }, "specular coefficient");
  expect([](Scene& s) { s.primitives[3].material = 99; },
         "primitive 3: material index 99 is out of range");
  expect([](Scene& s) { s.primitives[4].q.c = {}; }, "primitive 4: quadric is degenerate");
  expect([](Scene& s) { s.origins.pop_back(); }, "source locations");
  expect([](Scene& s) { s.threshold = 1; }, "threshold");
  expect([](Scene& s) { s.max_depth = 0; }, "max_depth");
  expect([](Scene& s) { s.spawn_offset = -1; }, "spawn_offset");
  expect([](Scene& s) { s.grid.resolution = {4, 0, 4}; }, "grid resolution");
  expect([](Scene& s) { s.grid.resolution = {4096, 4096, 4096}; }, "too many voxels");
}

}  // namespace
}  // namespace rtm
