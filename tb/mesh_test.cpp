// `rtm render` of mesh files: a small OBJ on the reference and the machine, bad files (exit 1, the
// file and the problem named, no image), and every OBJ, PLY, STL, OFF and glTF file of Debian's
// assimp-testmodels (docs/studies/mesh-corpus.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <atomic>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "cli_test_support.h"
#include "render/image_io.h"

namespace rtm::test {
namespace {

const std::string kCube =
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";

TEST(MeshRender, ObjOnTheReferenceAndTheMachine) {
  Tmp tmp;
  spit(tmp / "cube.obj", kCube);
  const nlohmann::json ref = render(tmp, "ref", tmp / "cube.obj" + " --reference --size 24x24");
  ASSERT_FALSE(ref.is_null());
  EXPECT_EQ(ref["primitives"], 12);
  const nlohmann::json machine = render(tmp, "machine", tmp / "cube.obj" + " --size 24x24 --pes 2");
  ASSERT_FALSE(machine.is_null());
  EXPECT_EQ(machine["primitives"], 12);
  EXPECT_GT(machine["rays"]["primary"].get<int>() + 0, 0) << machine.dump();
}

TEST(MeshRender, BadMeshFileExitsOneNamingIt) {
  Tmp tmp;
  spit(tmp / "bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n");
  const Proc r = run_rtm(
      "render " + tmp / "bad.ply" + " --reference -q --size 8x8 --out " + tmp / "b.png", tmp);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("rtm: " + tmp / "bad.ply" + ":0: ", 0), 0u) << r.err;
  EXPECT_FALSE(std::filesystem::exists(tmp / "b.png"));
}

TEST(MeshRender, DegenerateTrianglesWarnAndStrictRefuses) {
  Tmp tmp;
  spit(tmp / "deg.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n");
  const Proc r = run_rtm(
      "render " + tmp / "deg.obj" + " --reference -q --size 8x8 --out " + tmp / "d.png", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(
      r.err.find("rtm: warning: " + tmp / "deg.obj" + ":0: skipped 1 degenerate triangle record ("),
      std::string::npos)
      << r.err;
  const Proc s = run_rtm(
      "render " + tmp / "deg.obj" + " --reference -q --strict --size 8x8 --out " + tmp / "s.png",
      tmp);
  EXPECT_EQ(s.exit_code, 1);
  EXPECT_EQ(s.err,
            "rtm: " + tmp / "deg.obj" + ":0: triangle 1: polygon has zero area (--strict)\n");
}

TEST(MeshRender, CameraOnTheCommandLine) {
  Tmp tmp;
  spit(tmp / "cube.obj", kCube);
  // Looking at the cube from far away down -z: it covers the middle only; from close, every pixel.
  const std::string args = tmp / "cube.obj" + " --reference --size 16x16 --camera ";
  render(tmp, "far", args + "'{eye: [0, 0, 40], look_at: [0, 0, 0], fov: 20}'");
  render(tmp, "near", args + "'{eye: [0, 0, 1.5], look_at: [0, 0, 0]}'");
  auto hits = [&](const std::string& name) {
    int n = 0;
    for (const int32_t id : rtm::read_id_map(tmp / (name + "-id.exr")).ids) n += id >= 0;
    return n;
  };
  // A 2-unit cube 40 away in a 20° view spans 2 / (2 × 40 × tan 10°) = 14% of the width: about 5 of
  // 256 pixels.
  EXPECT_GT(hits("far"), 0);
  EXPECT_LT(hits("far"), 20);
  EXPECT_EQ(hits("near"), 256);  // inside the cube's front face's view
  const Proc bad = run_rtm("render " + args + "'{fov: 200}' -q --out " + tmp / "b.png", tmp);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.err, "rtm: --camera: camera.fov: must be in (0, 180) degrees, got 200\n");
  const Proc typo =
      run_rtm("render " + args + "'{eyes: [0, 0, 1]}' -q --out " + tmp / "b.png", tmp);
  EXPECT_EQ(typo.exit_code, 2);
  EXPECT_NE(typo.err.find("unknown key 'eyes'"), std::string::npos) << typo.err;
}

/// A mesh of about n triangles from scripts/mesh-generate (a rippled torus), at `path`; returns
/// how many it has, as the script says ("PATH: N triangles, M vertices").
int generate_mesh(const Tmp& tmp, int n, const std::string& path) {
  const Proc g = sh(std::string("python3 ") + RTM_SOURCE_DIR + "/scripts/mesh-generate " +
                        std::to_string(n) + " " + path,
                    tmp);
  EXPECT_EQ(g.exit_code, 0) << g.err;
  const size_t at = g.out.find(": ");
  return at == std::string::npos ? 0 : std::stoi(g.out.substr(at + 2));
}

// A large mesh is held to the memory budget before anything frame-sized is allocated: the
// estimate counts its primitives, their copies and their memory images, so a budget below it is
// refused naming the scene, and one above it renders (the watch would stop a render that
// outgrew it).
TEST(MeshScale, TheMemoryBudgetHoldsOnALargeMesh) {
  Tmp tmp;
  const int triangles = generate_mesh(tmp, 200000, tmp / "torus.ply");
  ASSERT_GT(triangles, 190000);
  const std::string args = "render " + tmp / "torus.ply" +
                           " --reference --threads 2 -q --size 32x32 --out " + tmp / "t.png";
  const Proc small = run_rtm(args + " --max-memory 200M", tmp);
  EXPECT_EQ(small.exit_code, 2) << small.err;
  EXPECT_NE(small.err.find("the largest part is the scene: "), std::string::npos) << small.err;
  EXPECT_NE(small.err.find("for " + std::to_string(triangles) + " primitives at "),
            std::string::npos)
      << small.err;
  EXPECT_FALSE(std::filesystem::exists(tmp / "t.png"));
  // The estimate, from the refusal's total, within the budget it is run under.
  const size_t at = small.err.find("needs about ");
  ASSERT_NE(at, std::string::npos);
  const double mib = std::stod(small.err.substr(at + 12));
  ASSERT_NE(small.err.find(" MiB, more than", at), std::string::npos) << small.err;
  EXPECT_GT(mib, 400);  // 200000 triangles: about a kilobyte and a half each, and the program
  const Proc enough = sh("/usr/bin/time -f %M -o " + tmp / "peak" + " " + RTM_BINARY + " " + args +
                             " --max-memory " + std::to_string(int(mib + 20)) + "M",
                         tmp);
  ASSERT_EQ(enough.exit_code, 0) << enough.err;
  const double peak_mib = std::stod(slurp(tmp / "peak")) / 1024;  // GNU time: kilobytes
  EXPECT_LT(peak_mib, mib + 20);
}

// Each PE's copy of a mesh must fit its local memory: a PE it does not fit is refused before
// the simulation, with the sizes, as for any scene.
TEST(MeshScale, APeWhoseSceneCopyDoesNotFitIsRefusedWithTheSizes) {
  Tmp tmp;
  generate_mesh(tmp, 10000, tmp / "torus.ply");
  const Proc r = run_rtm("render " + tmp / "torus.ply" +
                             " --pes 2 --size 16x16 -q --set local_memory_bytes=1000000 --out " +
                             tmp / "t.png",
                         tmp);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("rtm: local memory too small: PE 0 needs ", 0), 0u) << r.err;
  // 10000 triangles: their records alone are more than a megabyte.
  const size_t at = r.err.find("(primitives ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_GT(std::stoll(r.err.substr(at + 12)), 1000000) << r.err;
  EXPECT_NE(r.err.find(" B, voxel data ", at), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("but local_memory_bytes is 1000000"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(tmp / "t.png"));
}

/// POV-Ray's ID image decoded to primitive numbers (-1: background), as `rtm pov --id` encodes
/// them.
std::vector<int32_t> pov_ids(const std::string& png) {
  std::vector<int32_t> ids;
  for (const rtm::Vec3& c : rtm::read_image(png).rgb)
    ids.push_back((int(std::lround(c.x * 255)) << 16 | int(std::lround(c.y * 255)) << 8 |
                   int(std::lround(c.z * 255))) -
                  1);
  return ids;
}

// `rtm pov` writes a mesh file's triangles as mesh2, and POV-Ray's primary rays hit the
// triangles ours hit: a rippled torus of 2,000 triangles seen whole, so that most of its
// pixels lie near a shared edge.
TEST(MeshPov, Mesh2AgreesWithPovRaysPrimaryHits) {
  if (std::system("command -v povray >/dev/null 2>&1") != 0)
    FAIL() << "povray is not installed (Debian package povray; scripts/setup installs it)";
  Tmp tmp;
  const int triangles = generate_mesh(tmp, 2000, tmp / "torus.ply");
  const std::string size = " --size 160x120";
  const nlohmann::json ours = render(tmp, "ours", tmp / "torus.ply --reference" + size);
  ASSERT_FALSE(ours.is_null());
  ASSERT_EQ(ours["primitives"], triangles);
  ASSERT_EQ(run_rtm("pov " + tmp / "torus.ply" + size + " --out " + tmp / "t.pov", tmp).exit_code,
            0);
  ASSERT_EQ(
      run_rtm("pov " + tmp / "torus.ply" + size + " --id --out " + tmp / "tid.pov", tmp).exit_code,
      0);
  const std::string text = slurp(tmp / "t.pov");
  EXPECT_LT(std::count(text.begin(), text.end(), '\n'), 3 * triangles);  // shared corners once
  EXPECT_NE(text.find("mesh2 {"), std::string::npos);
  EXPECT_EQ(text.find("polygon {"), std::string::npos);
  const Proc r = sh("povray +I" + tmp / "tid.pov" + " +O" + tmp / "pov-id.png" +
                        " +W160 +H120 -D -A +FN8 File_Gamma=1.0 +WT1",
                    tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<int32_t> theirs = pov_ids(tmp / "pov-id.png");
  const std::vector<int32_t> mine = rtm::read_id_map(tmp / "ours-id.exr").ids;
  ASSERT_EQ(mine.size(), theirs.size());
  int same = 0, hit = 0;
  for (size_t i = 0; i < mine.size(); ++i) same += mine[i] == theirs[i], hit += mine[i] >= 0;
  EXPECT_GT(hit, int(mine.size()) / 4);  // the torus fills a good part of the view
  std::cout << same << " of " << mine.size() << " pixels show the same triangle (" << hit
            << " on the torus)\n";
  EXPECT_GE(double(same) / double(mine.size()), 0.999)
      << same << " of " << mine.size() << " pixels agree";
  // The shaded scene parses and renders too.
  const Proc shaded = sh("povray +I" + tmp / "t.pov" + " +O" + tmp / "pov.png" +
                             " +W160 +H120 -D -A +FN8 File_Gamma=1.0 +WT1",
                         tmp);
  EXPECT_EQ(shaded.exit_code, 0) << shaded.err;
}

// The same triangles as an OBJ file and as NFF polygons, in the same order. Their corners are
// dyadic, so Assimp's single-precision reading keeps them exact: a pyramid on a floor.
const std::vector<std::array<double, 9>> kPyramid = {{-1, 1.5, 0, 1, 0, 1, 1, 0, -1},
                                                     {-1, 1.5, 0, 1, 0, -1, -1, 0, -1},
                                                     {-1, 1.5, 0, -1, 0, -1, -1, 0, 1},
                                                     {-1, 1.5, 0, -1, 0, 1, 1, 0, 1},
                                                     {-4, 0, -4, -4, 0, 4, 4, 0, 4},
                                                     {-4, 0, -4, 4, 0, 4, 4, 0, -4},
                                                     {0.5, 0.75, 1.5, 1.5, 0, 2.5, 2.5, 0, 0.5}};

std::string pyramid_obj() {
  std::ostringstream o;
  for (const auto& t : kPyramid)
    for (int k = 0; k < 3; ++k)
      o << "v " << t[3 * k] << " " << t[3 * k + 1] << " " << t[3 * k + 2] << "\n";
  for (size_t i = 0; i < kPyramid.size(); ++i)
    o << "f " << 3 * i + 1 << " " << 3 * i + 2 << " " << 3 * i + 3 << "\n";
  return o.str();
}

const std::string kView =
    "v from 3 4 6 at 0 0.5 0 up 0 1 0 angle 40 hither 1 resolution 64 48\nb 0.1 0.1 0.2\nl 4 8 6\n"
    "f 0.8 0.6 0.4 0.7 0.2 0 0 0\n";

std::string pyramid_nff() {
  std::ostringstream o;
  o << kView;
  for (const auto& t : kPyramid) {
    o << "p 3\n";
    for (int k = 0; k < 3; ++k) o << t[3 * k] << " " << t[3 * k + 1] << " " << t[3 * k + 2] << "\n";
  }
  return o.str();
}

/// The NFF's camera, light and material as the native format states them (docs/scene-format.md,
/// "NFF": one light at sqrt(1)/2, the ambient light too, ambient = Kd), the triangles the OBJ's.
const std::string kPyramidYaml =
    "camera: {eye: [3, 4, 6], look_at: [0, 0.5, 0], up: [0, 1, 0], fov: 40, resolution: [64, 48]}\n"
    "background: [0.1, 0.1, 0.2]\nambient: [0.5, 0.5, 0.5]\nlights:\n  - {position: [4, 8, 6], "
    "color: [0.5, 0.5, 0.5]}\n"
    "materials:\n  f: {color: [0.8, 0.6, 0.4], ambient: 0.7, diffuse: 0.7, specular: 0.2}\n"
    "primitives:\n  - mesh: {file: pyramid.obj, material: f}\n";

// A mesh written as OBJ and as NFF polygons is the same geometry and the same picture: the
// same image to the bit, the same hit mask and, the face order kept, the same ID map, on the
// reference and on the machine.
TEST(MeshRender, ObjAndNffPolygonsGiveTheSamePicture) {
  Tmp tmp;
  spit(tmp / "pyramid.obj", pyramid_obj());
  spit(tmp / "pyramid.nff", pyramid_nff());
  spit(tmp / "pyramid.yaml", kPyramidYaml);
  for (const std::string renderer : {"--reference", "--pes 2"}) {
    SCOPED_TRACE(renderer);
    const nlohmann::json nff = render(tmp, "nff", tmp / "pyramid.nff " + renderer);
    const nlohmann::json obj = render(tmp, "obj", tmp / "pyramid.yaml " + renderer);
    ASSERT_FALSE(nff.is_null() || obj.is_null());
    EXPECT_EQ(nff["primitives"], int(kPyramid.size()));
    EXPECT_EQ(obj["primitives"], int(kPyramid.size()));
    const rtm::Image a = rtm::read_image(tmp / "nff.exr"), b = rtm::read_image(tmp / "obj.exr");
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    int differ = 0, lit = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
      differ += !(a.rgb[i].x == b.rgb[i].x && a.rgb[i].y == b.rgb[i].y && a.rgb[i].z == b.rgb[i].z);
      lit += a.rgb[i].x > 0.2;
    }
    EXPECT_EQ(differ, 0);
    EXPECT_GT(lit, 500);  // the floor and the pyramid fill most of the frame
    const std::vector<int32_t> ia = rtm::read_id_map(tmp / "nff-id.exr").ids,
                               ib = rtm::read_id_map(tmp / "obj-id.exr").ids;
    ASSERT_EQ(ia.size(), ib.size());
    int masks = 0, ids = 0, seen = 0;
    for (size_t i = 0; i < ia.size(); ++i)
      masks += (ia[i] >= 0) != (ib[i] >= 0), ids += ia[i] != ib[i], seen += ia[i] >= 0;
    EXPECT_EQ(masks, 0);
    EXPECT_EQ(ids, 0);
    EXPECT_GT(seen, 1000);
    EXPECT_EQ(nff["rays"], obj["rays"]);
  }
}

/// A sphere of latitude-longitude triangles with its exact normals as OBJ `vn`: the case smooth
/// shading is for.
std::string faceted_sphere_obj() {
  std::ostringstream o;
  const int rings = 8, segments = 16;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double a = M_PI * i / rings, b = 2 * M_PI * j / segments;
      const Vec3 n(std::sin(a) * std::cos(b), std::cos(a), std::sin(a) * std::sin(b));
      o << "v " << n.x << " " << n.y << " " << n.z << "\nvn " << n.x << " " << n.y << " " << n.z
        << "\n";
    }
  auto at = [&](int i, int j) { return i * segments + (j % segments) + 1; };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (i > 0)
        o << "f " << a << "//" << a << " " << b << "//" << b << " " << d << "//" << d << "\n";
      if (i < rings - 1)
        o << "f " << b << "//" << b << " " << c << "//" << c << " " << d << "//" << d << "\n";
    }
  return o.str();
}

/// The share of pixels whose channels all lie within `tolerance`.
double share_within(const rtm::Image& a, const rtm::Image& b, double tolerance) {
  int within = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i)
    within +=
        std::abs(std::clamp(a.rgb[i].x, 0.0, 1.0) - std::clamp(b.rgb[i].x, 0.0, 1.0)) <=
            tolerance &&
        std::abs(std::clamp(a.rgb[i].y, 0.0, 1.0) - std::clamp(b.rgb[i].y, 0.0, 1.0)) <=
            tolerance &&
        std::abs(std::clamp(a.rgb[i].z, 0.0, 1.0) - std::clamp(b.rgb[i].z, 0.0, 1.0)) <= tolerance;
  return double(within) / double(a.rgb.size());
}

// Vertex normals shade smooth by default and flat in the paper preset, on the reference and the
// machine alike; the geometry (every primary hit) is the same either way, and the machine agrees
// with its reference in both.
TEST(MeshRender, VertexNormalsShadeSmoothByDefaultAndFlatInThePaperPreset) {
  Tmp tmp;
  spit(tmp / "ball.obj", faceted_sphere_obj());
  const std::string args =
      tmp / "ball.obj --size 48x48 --camera '{eye: [0, 0, 4], look_at: [0, 0, 0]}'";
  const nlohmann::json smooth = render(tmp, "smooth", args + " --pes 2");
  const nlohmann::json flat = render(tmp, "flat", args + " --pes 2 --preset paper");
  const nlohmann::json ref_smooth = render(tmp, "ref-smooth", args + " --reference");
  const nlohmann::json ref_flat =
      render(tmp, "ref-flat", args + " --reference --set normal_interpolation=flat");
  ASSERT_FALSE(smooth.is_null() || flat.is_null() || ref_smooth.is_null() || ref_flat.is_null());
  EXPECT_EQ(smooth["config"]["normal_interpolation"], "barycentric");
  EXPECT_EQ(flat["config"]["normal_interpolation"], "flat");
  EXPECT_EQ(rtm::read_id_map(tmp / "smooth-id.exr").ids, rtm::read_id_map(tmp / "flat-id.exr").ids);
  EXPECT_EQ(rtm::read_id_map(tmp / "ref-smooth-id.exr").ids,
            rtm::read_id_map(tmp / "ref-flat-id.exr").ids);
  const rtm::Image s = rtm::read_image(tmp / "ref-smooth.exr"),
                   f = rtm::read_image(tmp / "ref-flat.exr");
  EXPECT_LT(share_within(s, f, 0.01), 0.9);  // smooth shading changes most lit pixels of the ball
  EXPECT_EQ(smooth["error"]["primary_ids_differing"], 0);
  EXPECT_GT(smooth["error"]["psnr_db"].get<double>(), 50) << smooth["error"].dump();
  EXPECT_GT(flat["error"]["psnr_db"].get<double>(), 50) << flat["error"].dump();
  // The smooth machine image is the smooth reference's, to fp32's rounding.
  EXPECT_GT(share_within(rtm::read_image(tmp / "smooth.exr"), s, 1.0 / 255), 0.99);
  // The interpolation costs shading cycles, and the normals local memory.
  auto shading_cycles = [](const nlohmann::json& j) {
    uint64_t c = 0;
    for (const auto& pe : j["per_pe"]) c += pe["busy_cycles"]["shading"].get<uint64_t>();
    return c;
  };
  const nlohmann::json plain =
      render(tmp, "plain", args + " --pes 2 --set normal_interpolation=flat");
  ASSERT_FALSE(plain.is_null());
  EXPECT_GT(shading_cycles(smooth), shading_cycles(plain));
  // 12 words more a triangle: its 3 normals and 3 reciprocals.
  const uint64_t more = smooth["memory"]["sections_bytes"]["primitives"].get<uint64_t>() -
                        plain["memory"]["sections_bytes"]["primitives"].get<uint64_t>();
  const uint64_t triangles = smooth["primitives"].get<uint64_t>();
  EXPECT_TRUE(more == 12 * 4 * triangles || more == 12 * 8 * triangles)
      << more << " for " << triangles;
  EXPECT_EQ(rtm::read_id_map(tmp / "plain-id.exr").ids,
            rtm::read_id_map(tmp / "smooth-id.exr").ids);
}

// POV-Ray's smooth triangles (mesh2 normals) are lit as ours: the images agree within the
// tolerance docs/validation-povray.md uses (0.05 a channel).
TEST(MeshPov, SmoothNormalsAgreeWithPovRay) {
  if (std::system("command -v povray >/dev/null 2>&1") != 0)
    FAIL() << "povray is not installed (Debian package povray; scripts/setup installs it)";
  Tmp tmp;
  spit(tmp / "ball.obj", faceted_sphere_obj());
  const std::string size = " --size 64x64";
  ASSERT_FALSE(render(tmp, "ours", tmp / "ball.obj --reference" + size).is_null());
  ASSERT_EQ(run_rtm("pov " + tmp / "ball.obj" + size + " --out " + tmp / "b.pov", tmp).exit_code,
            0);
  EXPECT_NE(slurp(tmp / "b.pov").find("normal_indices"), std::string::npos);
  const Proc r = sh("povray +I" + tmp / "b.pov" + " +O" + tmp / "pov.exr" +
                        " +W64 +H64 -D -A +FE File_Gamma=1.0 +WT1",
                    tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double within =
      share_within(rtm::read_image(tmp / "ours.exr"), rtm::read_image(tmp / "pov.exr"), 0.05);
  std::cout << 100 * within << " % of pixels within 0.05 of POV-Ray's\n";
  EXPECT_GT(within, 0.99);
  ASSERT_EQ(run_rtm("pov " + tmp / "ball.obj" + size + " --normal-interpolation flat --out " +
                        tmp / "f.pov",
                    tmp)
                .exit_code,
            0);
  EXPECT_EQ(slurp(tmp / "f.pov").find("normal_indices"), std::string::npos);
  EXPECT_EQ(
      run_rtm("pov " + tmp / "ball.obj --normal-interpolation phong --out " + tmp / "x.pov", tmp)
          .exit_code,
      2);
}

/// Where Debian's assimp-testmodels puts its files.
const std::string kTestModels = "/usr/share/assimp/models";

TEST(MeshCorpus, EveryTestModelRendersOrFailsWithAMessage) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(kTestModels))
    GTEST_SKIP() << "assimp-testmodels is not installed (" << kTestModels << ")";
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(kTestModels)) {
    std::string ext = e.path().extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (e.is_regular_file() && (ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".off" ||
                                ext == ".gltf" || ext == ".glb"))
      files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GT(files.size(), 50u);
  Tmp tmp;
  std::atomic<size_t> next{0};
  std::mutex m;
  std::map<std::string, Proc> results;
  auto worker = [&] {
    for (size_t i; (i = next++) < files.size();) {
      const std::string& f = files[i];
      // A hang would be a finding: `timeout` ends it, and its exit code 137 fails the test.
      const std::string err = tmp / (std::to_string(i) + ".err");
      const int status =
          std::system(("timeout -s KILL 200 " + std::string(RTM_BINARY) + " render '" + f +
                       "' --reference -q --threads 1 --size 16x16 --out " +
                       tmp / (std::to_string(i) + ".png") + " >/dev/null 2>" + err + " </dev/null")
                          .c_str());
      Proc r;
      r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      r.err = slurp(err).substr(0, 2000);
      std::lock_guard<std::mutex> lock(m);
      results[f] = r;
    }
  };
  // The suite runs beside other tests: two at a time.
  std::thread a(worker), b(worker);
  a.join();
  b.join();
  int rendered = 0;
  for (const auto& [f, r] : results) {
    SCOPED_TRACE(f);
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << "exit " << r.exit_code << ": " << r.err;
    if (r.exit_code == 0) ++rendered;
    if (r.exit_code == 1) {
      EXPECT_EQ(r.err.rfind("rtm: " + f + ":", 0), 0u) << r.err;
    }
  }
  std::cout << rendered << " of " << files.size() << " files render\n";
  EXPECT_GT(rendered, int(files.size()) / 2);
}

}  // namespace
}  // namespace rtm::test
