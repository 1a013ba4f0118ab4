// `rtm pov`: a scene as POV-Ray 3.7 SDL. How each of our semantics maps onto POV-Ray's, and
// where it cannot, is in docs/validation-povray.md; the comments here say why each choice.
#include "pov_export.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <unordered_map>
#include <array>

#include <CLI/CLI.hpp>

#include "config/config.h"
#include "render/image_io.h"
#include "render/partial_files.h"
#include "render_options.h"
#include "scene/scene.h"

namespace rtm {
namespace {

/// Shortest decimal that reads back as the same double: the exported geometry is exact, so
/// silhouettes in POV-Ray land where ours do.
std::string num(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

std::string vec(const Vec3& v) { return "<" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ">"; }

/// The clip half-spaces n·p + d <= 0 as POV planes. POV normalises a plane's normal and keeps
/// `plane { n, dist }`'s inside at n̂·p < dist, so the distance is −d / |n|.
void write_clips(std::ostream& o, const std::vector<HalfSpace>& clips) {
  if (clips.empty()) return;
  o << "  clipped_by { intersection {\n";
  for (const HalfSpace& h : clips) {
    const double len = length(h.n);
    o << "    plane { " << vec(h.n / len) << ", " << num(-h.d / len) << " }\n";
  }
  o << "  } }\n";
}

void write_shape(std::ostream& o, const Primitive& p, bool smooth) {
  switch (p.kind) {
    case ShapeKind::Sphere:
      o << "sphere { " << vec(p.p0) << ", " << num(p.r0) << "\n";
      return;
    case ShapeKind::Cylinder:
    case ShapeKind::Cone:
      // NFF `c` has no caps; POV's cone with equal radii is its cylinder.
      o << "cone { " << vec(p.p0) << ", " << num(p.r0) << ", " << vec(p.p1) << ", " << num(p.r1)
        << " open\n";
      return;
    case ShapeKind::Polygon: {
      if (smooth) {  // POV-Ray blends a smooth_triangle's normals by the same barycentric weights
        o << "smooth_triangle { " << vec(p.vertices[0]) << ", " << vec(p.normals[0]) << ", "
          << vec(p.vertices[1]) << ", " << vec(p.normals[1]) << ", " << vec(p.vertices[2]) << ", "
          << vec(p.normals[2]) << "\n";
        return;
      }
      // A concave polygon's pieces are written as the whole polygon, once, so POV-Ray's own
      // polygon checks our decomposition (to_pov skips the other pieces).
      const std::vector<Vec3>& v = p.outline.empty() ? p.vertices : p.outline;
      o << "polygon { " << v.size() + 1;  // POV wants the outline closed
      for (const Vec3& x : v) o << ", " << vec(x);
      o << ", " << vec(v.front()) << "\n";
      return;
    }
    default: {
      // Everything else as the clipped quadric the machine itself intersects. POV orders the
      // cross terms xy, xz, yz; the paper's are D xy, E yz, F zx.
      const auto& c = p.q.c;
      o << "quadric { <" << num(c[kA]) << ", " << num(c[kB]) << ", " << num(c[kC]) << ">, <"
        << num(c[kD]) << ", " << num(c[kF]) << ", " << num(c[kE]) << ">, <" << num(c[kG]) << ", "
        << num(c[kH]) << ", " << num(c[kI]) << ">, " << num(c[kJ]) << "\n";
      write_clips(o, p.clips);
      // A little larger than the bound, so POV's bounding box cannot shave the surface.
      const Vec3 pad = 1e-6 * (p.bounds.extent() + Vec3(1));
      o << "  bounded_by { box { " << vec(p.bounds.lo - pad) << ", " << vec(p.bounds.hi + pad)
        << " } }\n";
      return;
    }
  }
}

/// POV-Ray scales a transparent surface's ambient and diffuse by its opacity 1 − transmit; ours
/// are independent of kt, so they are divided by it here (kt must stay below 1 for that).
constexpr double kMaxTransmit = 0.999;

void write_material(std::ostream& o, size_t i, const Material& m) {
  const double kt = std::min(m.transmission, kMaxTransmit);
  const double opacity = 1 - kt;
  o << "#declare M" << i << " = material {  // " << m.name << "\n"
    << "  texture {\n"
    << "    pigment { rgbt <" << num(m.color.x) << ", " << num(m.color.y) << ", " << num(m.color.z)
    << ", " << num(kt) << "> }\n"
    << "    finish { ambient " << num(m.ambient / opacity) << " diffuse "
    << num(m.diffuse / opacity) << " reflection " << num(m.specular)
    << " brilliance 1 specular 0 phong 0 }\n"
    << "  }\n"
    << "  interior { ior " << num(m.ior) << " }\n"
    << "}\n";
}

/// Ours: a transparent surface blocks shadow rays completely; POV's lets `transmit` through. An
/// opaque twin seen only by shadow rays restores our shadows. It must lie strictly inside: POV
/// moves a shadow ray to each transparent surface it crosses and then ignores hits closer than
/// its SMALL_TOLERANCE (1e-3), so a coincident twin is skipped whenever the glass wins the tie.
/// Only spheres get one (the only transparent shape in the SPD scenes); the gap leaves a sliver
/// of filtered light at the shadow's rim.
constexpr double kTwinGap = 2e-3;

void write_shadow_twin(std::ostream& o, const Primitive& p) {
  const double r = p.r0 - std::max(kTwinGap, 1e-3 * p.r0);
  if (p.kind != ShapeKind::Sphere || r <= 0) return;
  o << "sphere { " << vec(p.p0) << ", " << num(r)
    << " pigment { rgb 0 } no_image no_reflection }\n";
}

/// A triangle of a mesh file, a polygon of three corners at line 0 (docs/scene-format.md,
/// "Mesh files"), written with its neighbours as one `mesh2`.
bool mesh_triangle(const Scene& s, size_t i) {
  const Primitive& p = s.primitives[i];
  return !s.origins.empty() && s.origins[i].line == 0 && p.kind == ShapeKind::Polygon &&
         p.pieces == 1 && p.vertices.size() == 3;
}

/// A triangle shaded with its vertex normals (render/shade.h, shading_normal).
bool smooth_triangle(const Scene& s, size_t i) {
  const Primitive& p = s.primitives[i];
  return s.normal_interpolation == NormalInterpolation::Barycentric &&
         p.kind == ShapeKind::Polygon && p.vertices.size() == 3 && p.clips.size() == 3 &&
         p.normals.size() == 3;
}

/// The flat ID colour of primitive i: its number + 1 in 24 bits, so black stays the background.
std::string id_texture(size_t i) {
  const uint32_t k = uint32_t(i + 1);
  std::ostringstream o;
  o << "texture { pigment { rgb <" << (k >> 16 & 255) << ", " << (k >> 8 & 255) << ", " << (k & 255)
    << "> / 255 } finish { ambient 1 diffuse 0 reflection 0 specular 0 phong 0 } }";
  return o.str();
}

/// Triangles [first, last) as one mesh2: POV-Ray parses and bounds a million of them as one
/// object, where a million `polygon`s take minutes. Corners shared by triangles are written once
/// (the same doubles, so the same edges). With `id`, each face has its own flat colour.
void write_mesh2(std::ostream& o, const Scene& s, size_t first, size_t last, bool id) {
  struct Key {
    double x, y, z;
    bool operator==(const Key& k) const { return x == k.x && y == k.y && z == k.z; }
  };
  struct Hash {
    size_t operator()(const Key& k) const {
      return std::hash<double>()(k.x) * 31 * 31 + std::hash<double>()(k.y) * 31 +
             std::hash<double>()(k.z);
    }
  };
  // Each distinct vector once, and every face's three indices into the list.
  struct Indexed {
    std::unordered_map<Key, size_t, Hash> index;
    std::vector<Vec3> list;
    std::vector<std::array<size_t, 3>> faces;
    void add(const std::vector<Vec3>& corners) {
      std::array<size_t, 3> f{};
      for (size_t k = 0; k < 3; ++k) {
        const Vec3& v = corners[k];
        const auto [at, added] = index.emplace(Key{v.x, v.y, v.z}, list.size());
        if (added) list.push_back(v);
        f[k] = at->second;
      }
      faces.push_back(f);
    }
    void write_list(std::ostream& o, const char* name) const {
      o << "  " << name << " { " << list.size();
      for (const Vec3& v : list) o << ",\n    " << vec(v);
      o << "\n  }\n";
    }
    void write_faces(std::ostream& o, const char* name, bool ids) const {
      o << "  " << name << " { " << faces.size();
      for (size_t k = 0; k < faces.size(); ++k) {
        o << ",\n    <" << faces[k][0] << ", " << faces[k][1] << ", " << faces[k][2] << ">";
        if (ids) o << ", " << k;
      }
      o << "\n  }\n";
    }
  };
  Indexed corners, normals;
  const bool smooth = smooth_triangle(s, first);  // the run is all smooth or all flat
  for (size_t i = first; i < last; ++i) {
    corners.add(s.primitives[i].vertices);
    if (smooth) normals.add(s.primitives[i].normals);
  }
  o << "// " << first << ".." << last - 1 << ": " << last - first << " mesh triangles\nmesh2 {\n";
  corners.write_list(o, "vertex_vectors");
  if (smooth) normals.write_list(o, "normal_vectors");
  if (id) {
    o << "  texture_list { " << last - first;
    for (size_t i = first; i < last; ++i) o << ",\n    " << id_texture(i);
    o << "\n  }\n";
  }
  corners.write_faces(o, "face_indices", id);
  if (smooth) normals.write_faces(o, "normal_indices", false);
  if (!id) o << "  material { M" << s.primitives[first].material << " }\n";
  o << "}\n";
}

}  // namespace

std::string to_pov(const Scene& s, bool id) {
  std::ostringstream o;
  const Camera& cam = s.camera;
  o << "// " << s.name << ", exported by `rtm pov" << (id ? " --id" : "") << "`.\n"
    << "// Render: povray +I<this> +O<out>.png +W" << cam.width << " +H" << cam.height
    << " -D -A +FN File_Gamma=1.0\n"
    << "#version 3.7;\n";

  // Global settings: our ray tree (depth, threshold) and ambient light.
  const Vec3 ambient = id ? Vec3(1) : s.ambient_light;
  o << "global_settings { assumed_gamma 1.0 max_trace_level " << (id ? 1 : s.max_depth)
    << " adc_bailout " << num(s.threshold) << " ambient_light rgb " << vec(ambient) << " }\n";

  // Camera: the exact vectors of render/camera.cpp. POV shoots direction + u·right + v·up with u,
  // v in [-0.5, 0.5] at pixel centres, which is our ray for any handedness, so no look_at (which
  // would re-derive right for POV's left-handed system and mirror the image).
  const Vec3 forward = normalize(cam.look_at - cam.eye);
  const Vec3 right = normalize(cross(forward, cam.up));
  const Vec3 up = cross(right, forward);
  const double half_w = std::tan(cam.fov_deg * M_PI / 360.0);
  const double half_h = half_w * double(cam.height) / double(cam.width);
  o << "camera { perspective\n"
    << "  location " << vec(cam.eye) << "\n"
    << "  direction " << vec(forward) << "\n"
    << "  right " << vec(2 * half_w * right) << "\n"
    << "  up " << vec(2 * half_h * up) << "\n"
    << "}  // horizontal angle " << num(cam.fov_deg) << " degrees\n";

  o << "background { rgb " << vec(id ? Vec3(0) : s.background) << " }\n";
  if (!id) {
    for (const Light& l : s.lights)
      o << "light_source { " << vec(l.position) << " rgb " << vec(l.color) << " }\n";
    for (size_t i = 0; i < s.materials.size(); ++i) write_material(o, i, s.materials[i]);
  }

  for (size_t i = 0; i < s.primitives.size(); ++i) {
    const Primitive& p = s.primitives[i];
    if (mesh_triangle(s, i)) {
      // The run of mesh triangles from here (of one material, unless every face has its own
      // colour).
      size_t last = i + 1;
      while (last < s.primitives.size() && mesh_triangle(s, last) &&
             (id || s.primitives[last].material == p.material) &&
             smooth_triangle(s, last) == smooth_triangle(s, i))
        ++last;
      write_mesh2(o, s, i, last, id);
      i = last - 1;
      continue;
    }
    if (p.piece > 0) continue;  // written with piece 0, as the whole polygon
    o << "// " << i << ": " << shape_name(p.kind) << "\n";
    // For ID comparisons: primitives i .. i + pieces − 1 are this one polygon (ID i + 1 here).
    if (p.pieces > 1) o << "// polygon pieces " << i << " " << p.pieces << "\n";
    write_shape(o, p, smooth_triangle(s, i));
    if (id) {
      o << "  " << id_texture(i) << "\n}\n";
      continue;
    }
    o << "  material { M" << p.material << " }\n}\n";
    if (s.materials[size_t(p.material)].transmission > 0) write_shadow_twin(o, p);
  }
  return o.str();
}

CLI::App* add_pov_command(CLI::App& app, PovOptions& opt) {
  CLI::App* pov = app.add_subcommand(
      "pov", "Export a scene to POV-Ray 3.7 SDL (for validation against POV-Ray)");
  pov->add_option("scene", opt.scene,
                  "Scene file: .nff or .yaml (the built-in default scene if omitted)");
  pov->add_option("--size", opt.size,
                  "Image size WxH, or N for NxN (keeps the scene's horizontal field of view)");
  pov->add_flag("--id", opt.id,
                "Flat colours encoding primitive number + 1 (24 bits), for ID maps");
  pov->add_flag("--strict", opt.strict,
                "Degenerate shapes are errors instead of skipped (as rtm render --strict)");
  pov->add_flag("--skip-unknown", opt.skip_unknown,
                "Skip unknown NFF records (as rtm render --skip-unknown)");
  pov->add_option("--normal-interpolation", opt.normal_interpolation,
                  "flat or barycentric: triangles with vertex normals as smooth_triangle / mesh2 "
                  "normals (default: "
                  "the default preset's, barycentric; the paper preset's is flat)");
  pov->add_option("--out", opt.out, "The .pov file to write")->required();
  return pov;
}

int run_pov(const PovOptions& opt) {
  remove_partial_files_on_signals();  // the .pov file is written under a temporary name
  return run_command([&] {
    check_writable("--out", opt.out);
    SceneReadOptions read;
    read.strict = opt.strict;
    read.skip_unknown = opt.skip_unknown;
    Scene scene = opt.scene.empty() ? default_scene() : load_scene(opt.scene, read);
    for (const std::string& w : skipped_warnings(scene, opt.scene))
      std::cerr << "rtm: warning: " << w << "\n";
    if (!opt.size.empty()) apply_size(opt.size, scene);
    if (!opt.normal_interpolation.empty()) {
      MachineConfig c;  // the key's own parsing and message
      try {
        set_config(c, "normal_interpolation", opt.normal_interpolation);
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--normal-interpolation: ") + e.what());
      }
      scene.normal_interpolation = c.normal_interpolation;
    }
    if (opt.id && scene.primitives.size() >= (1u << 24) - 1)
      throw UsageError("--id: more primitives than 24 bits can number");
    write_text_atomically(opt.out, to_pov(scene, opt.id));
    std::printf("pov: %s (%s%zu primitives, %dx%d)\n", opt.out.c_str(),
                opt.id ? "ID colours, " : "", scene.primitives.size(), scene.camera.width,
                scene.camera.height);
    return 0;
  });
}

}  // namespace rtm
