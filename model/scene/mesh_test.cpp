// Mesh files through Assimp: each format on small files written here, materials, cameras, mixed
// YAML scenes, degenerate and bad faces, bad files, the encoding between the importing child and
// rtm (render/mesh_render_test.cpp renders a mesh against the same polygons in NFF).
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "scene/mesh.h"
#include "scene/mesh_test_files.h"
#include "scene/scene.h"

namespace rtm {
namespace {

namespace fs = std::filesystem;

class MeshFiles : public test::MeshFileTest {};
using test::kObj;

TEST_F(MeshFiles, ObjQuadIsTriangulated) {
  const Scene s = load_scene(write("quad.obj", kObj));
  ASSERT_EQ(s.primitives.size(), 3u);  // the quad as two triangles, and the triangle
  for (const Primitive& p : s.primitives) {
    EXPECT_EQ(p.kind, ShapeKind::Polygon);
    EXPECT_EQ(p.vertices.size(), 3u);
  }
  EXPECT_EQ(s.name, "quad");
  EXPECT_EQ(s.origins[0].file, (dir_ / "quad.obj").string());
  EXPECT_EQ(s.lights.size(), 1u);  // the default light
  EXPECT_TRUE(s.skipped.empty());
}

TEST_F(MeshFiles, EachFormatReadsTheSameTriangle) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 "
      "0 1 2\n";
  const std::string stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 "
      "0\nendloop\nendfacet\n"
      "endsolid t\n";
  const std::string off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  // Three float32 corners, base64 in a data URI (12 bytes each: 0 0 0, 1 0 0, 0 1 0).
  const std::string gltf = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0,
    "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]})";
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
           {"t.ply", ply},
           {"t.stl", stl},
           {"t.off", off},
           {"t.gltf", gltf}}) {
    SCOPED_TRACE(name);
    const Scene s = load_scene(write(name, text));
    ASSERT_EQ(s.primitives.size(), 1u);
    const Aabb b = s.primitives[0].bounds;
    EXPECT_NEAR(b.lo.x, 0, 1e-6);
    EXPECT_NEAR(b.hi.x, 1, 1e-6);
    EXPECT_NEAR(b.hi.y, 1, 1e-6);
    EXPECT_NEAR(b.hi.z - b.lo.z, 0, 1e-6);
  }
}

TEST_F(MeshFiles, GlbBinaryReads) {
  // A GLB: 12-byte header, a JSON chunk, a BIN chunk with the three corners.
  std::string json =
      R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"scene":0,"nodes":[{"mesh":0}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"buffers":[{"byteLength":36}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})";
  while (json.size() % 4) json += ' ';
  const float corners[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string bin(reinterpret_cast<const char*>(corners), sizeof corners);
  auto u32 = [](uint32_t x) { return std::string(reinterpret_cast<const char*>(&x), 4); };
  const std::string body =
      u32(uint32_t(json.size())) + "JSON" + json + u32(uint32_t(bin.size())) + "BIN" + '\0' + bin;
  const std::string glb = "glTF" + u32(2) + u32(uint32_t(12 + body.size())) + body;
  const Scene s = load_scene(write("t.glb", glb));
  ASSERT_EQ(s.primitives.size(), 1u);
  EXPECT_NEAR(s.primitives[0].bounds.hi.x, 1, 1e-6);
}

TEST_F(MeshFiles, ObjMaterialsMapToTheMachinesCoefficients) {
  write("m.mtl",
        "newmtl mirror\nKd 0.2 0.4 0.6\nKs 0.5 0.5 0.8\nNs 50\nNi 1.0\nd 1\nillum 3\n"
        "newmtl glass\nKd 1 1 1\nKs 0.3 0.3 0.3\nNi 1.5\nd 0.25\nillum 4\n"
        "newmtl plastic\nKd 0.8 0.1 0.1\nKs 1 1 1\nNs 10\nillum 2\n");
  const Scene s =
      load_scene(write("m.obj",
                       "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                       "usemtl mirror\nf 1 2 3\nusemtl glass\nf 1 2 4\nusemtl plastic\nf 1 3 4\n"));
  ASSERT_EQ(s.primitives.size(), 3u);
  const Material& mirror = s.materials[size_t(s.primitives[0].material)];
  EXPECT_NEAR(mirror.color.y, 0.4, 1e-6);
  EXPECT_NEAR(mirror.diffuse, 0.9, 1e-12);
  EXPECT_NEAR(mirror.specular, 0.6, 1e-6);  // the mean of Ks, as illum 3 traces reflections
  EXPECT_EQ(mirror.transmission, 0);
  const Material& glass = s.materials[size_t(s.primitives[1].material)];
  EXPECT_NEAR(glass.transmission, 0.75, 1e-6);  // 1 - d
  EXPECT_NEAR(glass.diffuse, 0.9 * 0.25, 1e-6);
  EXPECT_NEAR(glass.ior, 1.5, 1e-6);
  EXPECT_NEAR(glass.specular, 0.3, 1e-6);
  const Material& plastic = s.materials[size_t(s.primitives[2].material)];
  EXPECT_EQ(plastic.specular, 0);  // illum 2's highlight: the machine has no highlight term
  EXPECT_NEAR(plastic.color.x, 0.8, 1e-6);
  EXPECT_EQ(plastic.name, "m.obj:plastic");
}

TEST(MeshMaterial, MetallicRoughnessMapping) {
  MeshMaterial gold;
  gold.base_color = Vec3(1, 0.8, 0.2);
  gold.metallic = 1;
  gold.roughness = 0.25;
  const Material g = machine_material(gold);
  EXPECT_EQ(g.diffuse, 0);
  EXPECT_DOUBLE_EQ(g.specular, 0.75);
  EXPECT_EQ(g.color, Vec3(1, 0.8, 0.2));
  MeshMaterial glass;
  glass.metallic = 0;
  glass.roughness = 0;
  glass.transmission = 0.9;
  const Material t = machine_material(glass);
  EXPECT_DOUBLE_EQ(t.transmission, 0.9);
  EXPECT_DOUBLE_EQ(t.ior, 1.5);  // glTF's default index of refraction
  EXPECT_EQ(t.specular, 0);
  MeshMaterial none;  // no keys at all: the default material
  const Material d = machine_material(none);
  EXPECT_EQ(d.color, Vec3(0.8));
  EXPECT_DOUBLE_EQ(d.diffuse, 0.9);
  EXPECT_EQ(d.specular, 0);
  MeshMaterial wild;  // values a file may hold: clamped into the machine's ranges
  wild.kd = Vec3(-1, std::nan(""), 2);
  wild.opacity = 7;
  wild.illum = 5;
  wild.ks = Vec3(3);
  const Material w = machine_material(wild);
  EXPECT_EQ(w.color, Vec3(0, 0, 2));
  EXPECT_EQ(w.transmission, 0);
  EXPECT_EQ(w.specular, 1);
}

TEST_F(MeshFiles, GltfCameraAndPointLightAreTheFiles) {
  const std::string gltf =
      R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0, 1, 2]}], "scene": 0,
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 0.5, 0.5], "intensity": 4}]}},
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1, "znear": 0.1}}],
    "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 5]}, {"translation": [2, 3, 4], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]})";
  const Scene s = load_scene(write("cam.gltf", gltf));
  EXPECT_NEAR(s.camera.eye.z, 5, 1e-6);
  EXPECT_NEAR(s.camera.eye.x, 0, 1e-6);
  EXPECT_LT(s.camera.look_at.z, 5);                       // a glTF camera looks along its -z
  EXPECT_NEAR(s.camera.fov_deg, 0.8 * 180 / M_PI, 1e-4);  // yfov 0.8 rad at aspect 1
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_NEAR(s.lights[0].position.x, 2, 1e-6);
  EXPECT_NEAR(s.lights[0].position.z, 4, 1e-6);
  EXPECT_NEAR(std::max({s.lights[0].color.x, s.lights[0].color.y, s.lights[0].color.z}), 1,
              1e-6);  // scaled to 1
  EXPECT_NEAR(s.lights[0].color.y / s.lights[0].color.x, 0.5, 1e-6);
}

TEST_F(MeshFiles, NoCameraFramesTheBox) {
  const Scene s = load_scene(write("quad.obj", kObj));
  Aabb box;
  for (const Primitive& p : s.primitives) box.extend(p.bounds);
  const Camera c = framing_camera(box);
  EXPECT_EQ(s.camera.eye, c.eye);
  const Vec3 centre = 0.5 * (box.lo + box.hi);
  EXPECT_NEAR(length(c.look_at - centre), 0, 1e-12);
  // The bounding sphere just fits the 45° view.
  const double r = 0.5 * length(box.extent());
  EXPECT_NEAR(r / length(c.eye - centre), std::sin(22.5 * M_PI / 180), 1e-12);
}

TEST_F(MeshFiles, DegenerateTrianglesAreSkippedOrWithStrictAnError) {
  const std::string path =
      write("deg.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\n"
            "f 1 2 4\nf 1 2 3\nf 1 1 4\nf 2 3 4\n");  // 2: on one line; 3: a repeated corner
  const Scene s = load_scene(path);
  EXPECT_EQ(s.primitives.size(), 2u);
  ASSERT_EQ(s.skipped.size(), 1u);
  EXPECT_EQ(s.skipped[0].kind, "degenerate triangle");
  EXPECT_EQ(s.skipped[0].count, 2);
  EXPECT_NE(s.skipped[0].reason.find("triangle 1 of " + path), std::string::npos)
      << s.skipped[0].reason;
  const std::vector<std::string> w = skipped_warnings(s, path);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].rfind(path + ":0: skipped 2 degenerate triangle records (", 0), 0u) << w[0];
  try {
    load_scene(path, {true, false});
    FAIL() << "strict reading accepted a degenerate triangle";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), path + ":0: triangle 1: polygon has zero area (--strict)");
  }
}

TEST_F(MeshFiles, BadFilesNameTheFileAndTheProblem) {
  auto message = [](const std::string& path) {
    try {
      load_scene(path);
    } catch (const SceneError& e) {
      EXPECT_EQ(e.file(), path);
      return std::string(e.what());
    }
    ADD_FAILURE() << path << " was read";
    return std::string();
  };
  EXPECT_EQ(
      message((dir_ / "missing.obj").string()),
      (dir_ / "missing.obj").string() + ":0: cannot read mesh file: No such file or directory");
  EXPECT_NE(message(write("garbage.ply", "ply\nthis is not a ply file\n"))
                .find("Assimp cannot read it: "),
            std::string::npos);
  EXPECT_NE(message(write("empty.obj", "")).find(":0: "), std::string::npos);
  EXPECT_NE(message(write("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n")).find("no triangles"),
            std::string::npos);
  fs::create_directories(dir_ / "folder.obj");
  EXPECT_NE(message((dir_ / "folder.obj").string()).find("not a regular file"), std::string::npos);
  EXPECT_NE(message(write("x.unknownext", "v 0 0 0\n")).find("unknown scene file extension"),
            std::string::npos);
}

TEST_F(MeshFiles, AnImportOverItsMemoryLimitIsAnError) {
  if (!import_memory_is_limited())
    GTEST_SKIP() << "sanitizer builds import without an address-space limit";
  // An OFF header that promises a billion vertices: Assimp reserves them before reading any.
  const std::string path = write("huge.off", "OFF\n1000000000 1000000000 0\n0 0 0\n");
  SceneReadOptions o;
  o.import_memory = uint64_t(256) << 20;
  try {
    load_scene(path, o);
    FAIL() << "read";
  } catch (const SceneError& e) {
    EXPECT_EQ(
        std::string(e.what()).rfind(
            path + ":0: out of memory: Assimp needed more than the import's limit of 256 MiB", 0),
        0u)
        << e.what();
  }
}

TEST_F(MeshFiles, YamlSceneMixesQuadricsAndPlacedMeshes) {
  write("tri.obj", "mtllib tri.mtl\nusemtl blue\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write("tri.mtl", "newmtl blue\nKd 0 0 1\n");
  fs::create_directories(dir_ / "sub");
  const std::string yaml = write("sub/scene.yaml",
                                 "camera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\n"
                                 "materials: {red: {color: [1, 0, 0]}}\n"
                                 "primitives:\n"
                                 "  - {sphere: {center: [0, 0, 0], radius: 1}, material: red}\n"
                                 "  - mesh: {file: ../tri.obj, scale: 2, translate: [5, 0, 0]}\n"
                                 "  - mesh: {file: ../tri.obj, material: red}\n");
  const Scene s = load_scene(yaml);
  ASSERT_EQ(s.primitives.size(), 3u);
  EXPECT_NEAR(s.primitives[1].bounds.lo.x, 5, 1e-9);
  EXPECT_NEAR(s.primitives[1].bounds.hi.x, 7, 1e-9);
  EXPECT_NEAR(s.primitives[1].bounds.hi.y, 2, 1e-9);
  EXPECT_EQ(s.materials[size_t(s.primitives[1].material)].color, Vec3(0, 0, 1));
  EXPECT_EQ(s.materials[size_t(s.primitives[2].material)].name, "red");
  EXPECT_EQ(s.origins[1].file, (dir_ / "sub" / ".." / "tri.obj").string());

  const std::string bad = write("bad.yaml",
                                "camera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\n"
                                "primitives:\n"
                                "  - mesh: {file: nowhere.obj}\n");
  try {
    load_scene(bad);
    FAIL() << "read";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              bad + ":3: primitives[0].mesh.file: " + (dir_ / "nowhere.obj").string() +
                  ":0: cannot read mesh file: No such file or directory");
  }
  const std::string unknown = write("unknown.yaml",
                                    "camera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\n"
                                    "primitives:\n"
                                    "  - mesh: {file: tri.obj, material: green}\n");
  EXPECT_THROW(load_scene(unknown), SceneError);
}

TEST(MeshData, BadIndicesAndCornersAreErrors) {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 3}};
  m.triangle_material = {0};
  Scene s;
  try {
    add_mesh(s, m, "f.obj", {}, {});
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              "f.obj:0: triangle 0: vertex index 3 is out of range (the mesh has 3 vertices)");
  }
  m.triangles = {{0, 1, 2}};
  m.positions[1].x = std::nan("");
  EXPECT_THROW(add_mesh(s, m, "f.obj", {}, {}), SceneError);
  m.positions[1].x = 1e200;
  EXPECT_THROW(add_mesh(s, m, "f.obj", {}, {}), SceneError);
  m.positions[1].x = 1;
  m.triangle_material = {4};
  EXPECT_THROW(add_mesh(s, m, "f.obj", {}, {}), SceneError);  // no such material
}

TEST(MeshData, EncodingRoundTripsAndRefusesBrokenBytes) {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  m.triangle_material = {0};
  MeshMaterial x;
  x.name = "a";
  x.kd = Vec3(0.5);
  x.illum = 3;
  m.materials = {x};
  m.camera = MeshCamera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40};
  m.lights = {{{1, 2, 3}, {1, 1, 1}}};
  m.points_and_lines = 7;
  m.normals.assign(m.positions.size(), Vec3(0, 0, 1));
  const std::string bytes = encode_mesh(m);
  const MeshData back = decode_mesh(bytes);
  EXPECT_EQ(back.positions, m.positions);
  EXPECT_EQ(back.triangles, m.triangles);
  EXPECT_EQ(back.materials[0].name, "a");
  EXPECT_EQ(*back.materials[0].illum, 3);
  EXPECT_FALSE(back.materials[0].ks);
  EXPECT_EQ(back.camera->fov_deg, 40);
  EXPECT_EQ(back.lights[0].position, Vec3(1, 2, 3));
  EXPECT_EQ(back.points_and_lines, 7u);
  EXPECT_EQ(back.normals, m.normals);
  // Every shorter prefix, and one byte more, is refused, but the one that ends where the normals
  // begin: an encoding made before normals were read (the fuzz corpus's), which has none.
  const size_t without_normals = bytes.size() - 8 - m.normals.size() * sizeof(Vec3);
  for (size_t n = 0; n < bytes.size(); ++n) {
    if (n == without_normals) continue;
    EXPECT_THROW(decode_mesh(bytes.substr(0, n)), std::invalid_argument) << n;
  }
  EXPECT_TRUE(decode_mesh(bytes.substr(0, without_normals)).normals.empty());
  EXPECT_THROW(decode_mesh(bytes + "x"), std::invalid_argument);
  // A count far beyond the bytes is refused before anything is allocated.
  std::string huge = bytes;
  const uint64_t big = uint64_t(1) << 60;
  huge.replace(8, 8, std::string(reinterpret_cast<const char*>(&big), 8));
  EXPECT_THROW(decode_mesh(huge), std::invalid_argument);
}

}  // namespace
}  // namespace rtm
