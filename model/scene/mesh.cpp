// Mesh data to scene primitives, and its encoding between the importing child and rtm.
// The mappings are docs/scene-format.md's, "Mesh files".
#include "scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <type_traits>

#include "scene/scene_checks.h"

namespace rtm {

namespace {

constexpr char kMagic[8] = {'r', 't', 'm', 'm', 'e', 's', 'h', '1'};

class Writer {
 public:
  template <class T>
  void raw(const T& x) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.append(reinterpret_cast<const char*>(&x), sizeof x);
  }
  void text(const std::string& s) {
    raw(uint64_t(s.size()));
    out += s;
  }
  template <class T>
  void optional(const std::optional<T>& x) {
    raw(uint8_t(x.has_value()));
    if (x) raw(*x);
  }
  template <class T>
  void array(const std::vector<T>& v) {
    raw(uint64_t(v.size()));
    if (!v.empty()) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  std::string out;
};

class Reader {
 public:
  explicit Reader(const std::string& b) : b_(b) {}
  template <class T>
  T raw() {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    T x;
    std::memcpy(&x, b_.data() + at_, sizeof x);
    at_ += sizeof x;
    return x;
  }
  std::string text() {
    const uint64_t n = count(1);
    std::string s = b_.substr(at_, n);
    at_ += n;
    return s;
  }
  template <class T>
  std::optional<T> optional() {
    const uint8_t has = raw<uint8_t>();
    if (has > 1) throw std::invalid_argument("mesh encoding: bad optional flag");
    if (!has) return std::nullopt;
    return raw<T>();
  }
  template <class T>
  std::vector<T> array() {
    const uint64_t n = count(sizeof(T));
    std::vector<T> v(n);
    if (n)
      std::memcpy(v.data(), b_.data() + at_,
                  n * sizeof(T));  // an empty vector's data() may be null
    at_ += n * sizeof(T);
    return v;
  }
  /// A count of items of `size` bytes each that the rest of the bytes can hold.
  uint64_t count(size_t size) {
    const uint64_t n = raw<uint64_t>();
    if (n > (b_.size() - at_) / size)
      throw std::invalid_argument("mesh encoding: a count exceeds the bytes left");
    return n;
  }
  bool done() const { return at_ == b_.size(); }

 private:
  void need(size_t n) const {
    if (b_.size() - at_ < n) throw std::invalid_argument("mesh encoding: ends early");
  }
  const std::string& b_;
  size_t at_ = 0;
};

double mean(const Vec3& v) { return (v.x + v.y + v.z) / 3; }

/// A colour from a file: negative and non-finite components are clamped to 0, so a stray value
/// cannot make the material invalid.
Vec3 clean_colour(const Vec3& c) {
  auto f = [](double x) { return std::isfinite(x) && x > 0 ? x : 0.0; };
  return {f(c.x), f(c.y), f(c.z)};
}

double unit(double x) { return std::isfinite(x) ? std::clamp(x, 0.0, 1.0) : 0.0; }

/// The OBJ illumination models that trace a reflected ray (3 to 9); 0 to 2 have at most a
/// highlight, which the machine's shading has no term for.
bool traces_reflection(int illum) { return illum >= 3 && illum <= 9; }

}  // namespace

std::string encode_mesh(const MeshData& m) {
  Writer w;
  w.out.append(kMagic, sizeof kMagic);
  w.array(m.positions);
  w.array(m.triangles);
  w.array(m.triangle_material);
  w.raw(uint64_t(m.materials.size()));
  for (const MeshMaterial& x : m.materials) {
    w.text(x.name);
    w.optional(x.kd);
    w.optional(x.ks);
    w.optional(x.ns);
    w.optional(x.ni);
    w.optional(x.opacity);
    w.optional(x.illum);
    w.optional(x.base_color);
    w.optional(x.metallic);
    w.optional(x.roughness);
    w.optional(x.transmission);
  }
  w.raw(uint8_t(m.camera.has_value()));
  if (m.camera) {
    w.raw(m.camera->eye);
    w.raw(m.camera->look_at);
    w.raw(m.camera->up);
    w.raw(m.camera->fov_deg);
  }
  w.array(m.lights);
  w.raw(m.points_and_lines);
  w.raw(m.other_lights);
  w.array(m.normals);  // last, and optional: encodings made before normals were read stay valid
  return std::move(w.out);
}

MeshData decode_mesh(const std::string& bytes) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw std::invalid_argument("mesh encoding: not an rtm mesh");
  const std::string body = bytes.substr(sizeof kMagic);
  Reader r(body);
  MeshData m;
  m.positions = r.array<Vec3>();
  m.triangles = r.array<std::array<uint32_t, 3>>();
  m.triangle_material = r.array<uint32_t>();
  const uint64_t materials = r.count(1);  // every material takes at least a byte
  for (uint64_t i = 0; i < materials; ++i) {
    MeshMaterial x;
    x.name = r.text();
    x.kd = r.optional<Vec3>();
    x.ks = r.optional<Vec3>();
    x.ns = r.optional<double>();
    x.ni = r.optional<double>();
    x.opacity = r.optional<double>();
    x.illum = r.optional<int>();
    x.base_color = r.optional<Vec3>();
    x.metallic = r.optional<double>();
    x.roughness = r.optional<double>();
    x.transmission = r.optional<double>();
    m.materials.push_back(std::move(x));
  }
  const uint8_t has_camera = r.raw<uint8_t>();
  if (has_camera > 1) throw std::invalid_argument("mesh encoding: bad camera flag");
  if (has_camera) {
    MeshCamera c;
    c.eye = r.raw<Vec3>();
    c.look_at = r.raw<Vec3>();
    c.up = r.raw<Vec3>();
    c.fov_deg = r.raw<double>();
    m.camera = c;
  }
  m.lights = r.array<Light>();
  m.points_and_lines = r.raw<uint64_t>();
  m.other_lights = r.raw<uint64_t>();
  if (!r.done()) m.normals = r.array<Vec3>();
  if (!r.done()) throw std::invalid_argument("mesh encoding: bytes left over");
  if (m.triangle_material.size() != m.triangles.size())
    throw std::invalid_argument("mesh encoding: one material per triangle expected");
  if (!m.normals.empty() && m.normals.size() != m.positions.size())
    throw std::invalid_argument("mesh encoding: one normal per vertex expected");
  return m;
}

Material machine_material(const MeshMaterial& m) {
  Material out;
  out.name = m.name;
  const bool pbr = m.metallic || m.roughness || m.base_color;
  if (pbr) {
    // glTF metallic-roughness: a metal's colour is in its reflection, a dielectric's in its
    // diffuse term; only a smooth surface reflects a sharp ray.
    const double metallic = unit(m.metallic.value_or(1));  // glTF's defaults
    const double roughness = unit(m.roughness.value_or(1));
    out.color = clean_colour(m.base_color.value_or(Vec3(1)));
    out.diffuse = 0.9 * (1 - metallic);
    out.specular = metallic * (1 - roughness);
    out.transmission = unit(m.transmission.value_or(0));
    out.diffuse *= 1 - out.transmission;
    out.ior = m.ni && std::isfinite(*m.ni) && *m.ni > 0 ? *m.ni : out.transmission > 0 ? 1.5 : 1.0;
    return out;
  }
  // OBJ/MTL and the formats Assimp reads into the same keys.
  out.color = clean_colour(m.kd.value_or(Vec3(0.8)));
  const int illum = m.illum.value_or(2);
  const double opacity = unit(m.opacity.value_or(1));
  if (illum == 0) {
    out.ambient = 1;  // "colour on, ambient off": the colour as it is, unlit
    out.diffuse = 0;
  } else {
    out.diffuse = 0.9 * opacity;
  }
  out.specular = traces_reflection(illum) ? unit(mean(clean_colour(m.ks.value_or(Vec3(0))))) : 0;
  out.transmission = 1 - opacity;
  out.ior = m.ni && std::isfinite(*m.ni) && *m.ni > 0 ? *m.ni : 1.0;
  return out;
}

void add_mesh(Scene& s, const MeshData& m, const std::string& file, const MeshPlacement& placement,
              const SceneReadOptions& options) {
  auto fail = [&](const std::string& what) { throw SceneError(file, 0, what); };
  const int first_material = int(s.materials.size());
  if (!placement.material) {
    for (const MeshMaterial& x : m.materials) {
      Material mat = machine_material(x);
      mat.name = std::filesystem::path(file).filename().string() + ":" +
                 (x.name.empty() ? "material" : x.name);
      try {
        scene_checks::check_material(mat);
      } catch (const std::invalid_argument& e) {
        fail("material '" + x.name +
             "': " + e.what());  // unreachable: machine_material cleans every value
      }
      s.materials.push_back(std::move(mat));
    }
    if (m.materials.empty()) {
      Material mat = machine_material({});
      mat.name = std::filesystem::path(file).filename().string() + ":default";
      s.materials.push_back(std::move(mat));
    }
  }
  if (m.triangle_material.size() != m.triangles.size())
    fail("the mesh has not one material per triangle");
  if (!m.normals.empty() && m.normals.size() != m.positions.size())
    fail("the mesh has not one normal per vertex");
  const size_t kept_materials = placement.material ? 0 : std::max<size_t>(1, m.materials.size());
  SkippedRecords degenerate{"degenerate triangle", "", 0, {}};
  SkippedRecords flat{"vertex normal", "", 0, {}};
  // Reserved: growing a million primitives by doubling would hold half again as many for a moment.
  s.primitives.reserve(s.primitives.size() + m.triangles.size());
  s.origins.reserve(s.origins.size() + m.triangles.size());
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    if (options.progress && i % 4096 == 0)
      options.progress("mesh load", "triangle", i, m.triangles.size());
    const std::string name = "triangle " + std::to_string(i);
    std::vector<Vec3> v;
    for (const uint32_t k : m.triangles[i]) {
      if (k >= m.positions.size())
        fail(name + ": vertex index " + std::to_string(k) + " is out of range (the mesh has " +
             std::to_string(m.positions.size()) + " vertices)");
      const Vec3 p = placement.scale * m.positions[k] + placement.translate;
      if (!all_finite(p)) fail(name + ": vertex " + std::to_string(k) + " is not finite");
      if (max_abs(p) > kMaxCoordinate)
        fail(name + ": vertex " + std::to_string(k) + " is beyond +-1e150");
      v.push_back(p);
    }
    Primitive prim;
    try {
      prim = make_polygon(v);
    } catch (const DegenerateShape& e) {
      if (options.strict) fail(name + ": " + e.what() + " (--strict)");
      if (degenerate.count++ == 0)
        degenerate.reason = std::string(e.what()) + "; the first is " + name + " of " + file;
      continue;
    } catch (const std::invalid_argument& e) {
      fail(name + ": " + e.what());
    }
    // A uniform scale and a translation keep the normals' directions.
    if (!m.normals.empty()) {
      prim.normals =
          vertex_normals(prim, {m.normals[m.triangles[i][0]], m.normals[m.triangles[i][1]],
                                m.normals[m.triangles[i][2]]});
      if (prim.normals.empty() && flat.count++ == 0)
        flat.reason = std::string(kFlatNormalsReason) + "; the first is " + name + " of " + file;
    }
    if (placement.material) {
      prim.material = *placement.material;
    } else {
      const uint32_t k = m.triangle_material[i];
      if (k >= kept_materials)
        fail(name + ": material index " + std::to_string(k) + " is out of range (the mesh has " +
             std::to_string(m.materials.size()) + " materials)");
      prim.material = first_material + int(k);
    }
    s.primitives.push_back(std::move(prim));
    s.origins.push_back({file, 0});
  }
  if (degenerate.count) s.skipped.push_back(std::move(degenerate));
  if (flat.count) s.skipped.push_back(std::move(flat));
  if (m.points_and_lines)
    s.skipped.push_back({"point or line face",
                         "it has no area to render",
                         int(std::min<uint64_t>(m.points_and_lines, INT32_MAX)),
                         {}});
}

Camera framing_camera(const Aabb& box) {
  Camera c;
  const Vec3 centre = box.empty() ? Vec3(0) : 0.5 * (box.lo + box.hi);
  double radius = box.empty() ? 0 : 0.5 * length(box.extent());
  if (!(radius > 0) || !std::isfinite(radius)) radius = 1;
  // Far enough that the box's bounding sphere fits the 45° view, from above and to the right of
  // +z: most mesh files are y-up and face +z.
  const double distance = radius / std::sin(c.fov_deg / 2 * M_PI / 180);
  c.look_at = centre;
  c.eye = centre + distance * normalize(Vec3(1, 1, 2));
  c.up = {0, 1, 0};
  return c;
}

Scene mesh_scene(const MeshData& m, const std::string& file, const SceneReadOptions& options) {
  Scene s;
  s.name = std::filesystem::path(file).stem().string();
  add_mesh(s, m, file, {}, options);
  Aabb box;
  for (const Primitive& p : s.primitives) box.extend(p.bounds);
  const Camera framed = framing_camera(box);
  s.camera = framed;
  if (m.camera) {
    s.camera.eye = m.camera->eye;
    s.camera.look_at = m.camera->look_at;
    s.camera.up = m.camera->up;
    s.camera.fov_deg = m.camera->fov_deg;
    try {
      scene_checks::check_camera(s.camera);
    } catch (const std::invalid_argument& e) {
      throw SceneError(file, 0, std::string("the file's camera: ") + e.what());
    }
  }
  // The file's point lights; their colours are scaled together so that the brightest component
  // is at most 1 (glTF gives intensities in candela, the machine a brightness).
  double brightest = 0;
  for (const Light& l : m.lights) {
    try {
      scene_checks::check_light(l);
    } catch (const std::invalid_argument& e) {
      throw SceneError(file, 0, std::string("the file's light: ") + e.what());
    }
    brightest = std::max({brightest, l.color.x, l.color.y, l.color.z});
  }
  for (Light l : m.lights) {
    if (brightest > 1) l.color /= brightest;
    s.lights.push_back(l);
  }
  if (m.lights.empty()) {
    // Above and to the left of the framing camera, so that shadows show.
    const Vec3 centre = framed.look_at;
    const double distance = length(framed.eye - centre);
    s.lights.push_back({centre + distance * Vec3(-0.5, 1, 1), Vec3(1)});
  }
  if (m.other_lights)
    s.skipped.push_back({"light that is not a point",
                         "the machine's lights are points",
                         int(std::min<uint64_t>(m.other_lights, INT32_MAX)),
                         {}});
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    throw SceneError(file, 0, e.what());
  }
  return s;
}

}  // namespace rtm
