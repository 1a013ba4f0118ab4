// The native scene format: YAML, written by hand. Reference: docs/scene-format.md.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "geom/polygon.h"
#include "scene/scene.h"
#include "scene/mesh.h"
#include "scene/scene_checks.h"

namespace rtm {

namespace {

int line_of(const YAML::Node& n) {
  return n.IsDefined() && !n.Mark().is_null() ? n.Mark().line + 1 : 0;
}

std::string str(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

/// Refuses YAML aliases (`*name`) before the document is built: an alias repeats a whole subtree
/// for a few bytes, so a small file could ask for any amount of work (10 KB of aliases to one
/// 250-corner polygon took 2 s and made 125,000 primitives).
class NoAliases : public YAML::EventHandler {
 public:
  explicit NoAliases(const std::string& file) : file_(file) {}
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    throw SceneError(file_, mark.line + 1,
                     "YAML aliases (*name) are not supported: write the value out");
  }
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}

 private:
  const std::string& file_;
};

/// Every parse step knows its node, and where it is in the document
/// ("primitives[2].sphere.radius").
class NativeParser {
 public:
  NativeParser(const std::string& file, const SceneReadOptions& options)
      : file_(file), options_(options) {}

  /// `text`, a YAML mapping of camera keys, applied to `base`.
  Camera camera_override(const std::string& text, const Camera& base) {
    YAML::Node doc;
    try {
      doc = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw SceneError(file_, e.mark.is_null() ? 0 : e.mark.line + 1,
                       "YAML syntax error: " + e.msg);
    }
    scene_.camera = base;
    camera(doc, false);
    return scene_.camera;
  }

  Scene parse(const std::string& yaml) {
    YAML::Node doc;
    try {
      std::istringstream in(yaml);
      NoAliases no_aliases(file_);
      YAML::Parser(in).HandleNextDocument(no_aliases);  // the document Load reads
      doc = YAML::Load(yaml);
    } catch (const YAML::Exception& e) {
      throw SceneError(file_, e.mark.is_null() ? 0 : e.mark.line + 1,
                       "YAML syntax error: " + e.msg);
    }
    if (!doc.IsMap())
      fail(doc, "scene", "expected a mapping with at least 'camera' and 'primitives'");
    Map top(
        *this, doc, "scene",
        {"name", "camera", "background", "ambient", "lights", "materials", "render", "primitives"});
    scene_.name = std::filesystem::path(file_).stem().string();
    if (auto n = top.get("name")) scene_.name = name(*n);
    camera(top.required("camera"));
    if (auto n = top.get("background")) scene_.background = colour(*n, "background");
    if (auto n = top.get("ambient")) scene_.ambient_light = colour(*n, "ambient");
    if (auto n = top.get("lights")) lights(*n);
    if (auto n = top.get("materials")) materials(*n);  // before primitives, which name them
    if (auto n = top.get("render")) render(*n);
    primitives(top.required("primitives"));
    try {
      validate(scene_);
    } catch (const std::invalid_argument& e) {
      fail(doc, "scene", e.what());  // unreachable if the checks below are complete
    }
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const YAML::Node& n, const std::string& path,
                         const std::string& what) const {
    throw SceneError(file_, std::max(1, line_of(n)), path + ": " + what);
  }

  /// A mapping whose keys are checked against the allowed set: a typo must not pass silently.
  class Map {
   public:
    Map(const NativeParser& p, const YAML::Node& n, std::string path,
        std::initializer_list<const char*> allowed)
        : p_(p), node_(n), path_(std::move(path)) {
      if (!n.IsMap()) p.fail(n, path_, "expected a mapping {key: value, ...}");
      for (auto it = n.begin(); it != n.end(); ++it) {
        const YAML::Node key = it->first;
        if (!key.IsScalar()) p.fail(key, path_, "keys must be plain names");
        const std::string k = key.Scalar();
        bool ok = false;
        for (const char* a : allowed) ok = ok || k == a;
        if (!ok) p.fail(key, path_, "unknown key '" + k + "' (allowed: " + list(allowed) + ")");
        if (entries_.count(k)) p.fail(key, path_, "duplicate key '" + k + "'");
        entries_.emplace(k, it->second);
      }
    }
    std::optional<YAML::Node> get(const std::string& k) const {
      auto it = entries_.find(k);
      if (it == entries_.end()) return std::nullopt;
      return it->second;
    }
    YAML::Node required(const std::string& k) const {
      auto it = entries_.find(k);
      if (it == entries_.end()) p_.fail(node_, path_, "missing required key '" + k + "'");
      return it->second;
    }
    std::string path(const std::string& k) const { return path_ + "." + k; }
    size_t size() const { return entries_.size(); }

   private:
    static std::string list(std::initializer_list<const char*> allowed) {
      std::string s;
      for (const char* a : allowed) s += (s.empty() ? "" : ", ") + std::string(a);
      return s;
    }
    const NativeParser& p_;
    YAML::Node node_;
    std::string path_;
    std::map<std::string, YAML::Node> entries_;
  };

  // ---- values ----

  std::string text(const YAML::Node& n, const std::string& path) const {
    if (!n.IsScalar()) fail(n, path, "expected a string");
    return n.Scalar();
  }

  /// The name becomes part of output file names, so it must be a plain file name.
  std::string name(const YAML::Node& n) const {
    const std::string s = text(n, "name");
    bool ok = !s.empty() && s[0] != '.' && s.size() <= 100;
    for (const char c : s)
      ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
    if (!ok)
      fail(n, "name",
           "must be 1 to 100 letters, digits, '_', '-' or '.', not starting with '.', got '" + s +
               "'");
    return s;
  }

  double number(const YAML::Node& n, const std::string& path) const {
    if (!n.IsScalar()) fail(n, path, "expected a number");
    // from_chars, not yaml-cpp's stream conversion: locale-independent, and "010" is not octal.
    std::string_view t = n.Scalar();
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    double x = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), x);
    if (r.ec == std::errc::result_out_of_range)
      fail(n, path, "number '" + n.Scalar() + "' is out of range");
    const bool parsed = r.ec == std::errc() && r.ptr == t.data() + t.size();
    std::string lower(t);
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    const bool yaml_non_finite =
        lower == ".nan" || lower == ".inf" || lower == "-.inf";  // YAML's spellings
    if (!parsed && !yaml_non_finite) fail(n, path, "expected a number, got '" + n.Scalar() + "'");
    if (!parsed || !std::isfinite(x)) fail(n, path, "number '" + n.Scalar() + "' is not finite");
    return x;
  }

  double at_least(const YAML::Node& n, const std::string& path, double lo) const {
    const double x = number(n, path);
    if (x < lo) fail(n, path, "must be >= " + str(lo) + ", got " + str(x));
    return x;
  }

  double positive(const YAML::Node& n, const std::string& path) const {
    const double x = number(n, path);
    if (!(x > 0)) fail(n, path, "must be > 0, got " + str(x));
    return x;
  }

  int integer(const YAML::Node& n, const std::string& path, int lo) const {
    const double x = number(n, path);
    if (x != std::floor(x) || x > INT_MAX)
      fail(n, path, "expected a whole number, got '" + n.Scalar() + "'");
    if (x < lo) fail(n, path, "must be >= " + std::to_string(lo) + ", got " + str(x));
    return int(x);
  }

  std::vector<double> numbers(const YAML::Node& n, const std::string& path, size_t count,
                              const char* layout) const {
    if (!n.IsSequence() || n.size() != count)
      fail(n, path, "expected " + std::string(layout) + " (" + std::to_string(count) + " numbers)");
    std::vector<double> out;
    for (size_t i = 0; i < count; ++i)
      out.push_back(number(n[i], path + "[" + std::to_string(i) + "]"));
    return out;
  }

  Vec3 vec3(const YAML::Node& n, const std::string& path) const {
    const auto v = numbers(n, path, 3, "[x, y, z]");
    return {v[0], v[1], v[2]};
  }

  Vec3 colour(const YAML::Node& n, const std::string& path) const {
    const auto v = numbers(n, path, 3, "[r, g, b]");
    for (size_t i = 0; i < 3; ++i)
      if (v[i] < 0) fail(n[i], path, "colour components must be >= 0, got " + str(v[i]));
    return {v[0], v[1], v[2]};
  }

  Vec3 direction(const YAML::Node& n, const std::string& path) const {
    const Vec3 v = vec3(n, path);
    if (!(length(v) > 0) || !std::isfinite(length(v)))
      fail(n, path, "must be a non-zero finite vector");
    return v;
  }

  // ---- sections ----

  /// The scene's camera; `whole` false: only the keys given change `c` (rtm render --camera).
  void camera(const YAML::Node& n, bool whole = true) {
    Map m(*this, n, "camera", {"eye", "look_at", "up", "fov", "resolution"});
    Camera& c = scene_.camera;
    if (whole || m.get("eye")) c.eye = vec3(m.required("eye"), m.path("eye"));
    if (whole || m.get("look_at")) c.look_at = vec3(m.required("look_at"), m.path("look_at"));
    if (auto v = m.get("up")) c.up = vec3(*v, m.path("up"));
    if (auto v = m.get("fov")) {
      c.fov_deg = number(*v, m.path("fov"));
      if (!(c.fov_deg > 0 && c.fov_deg < 180))
        fail(*v, m.path("fov"), "must be in (0, 180) degrees, got " + str(c.fov_deg));
    }
    if (auto v = m.get("resolution")) {
      if (!v->IsSequence() || v->size() != 2)
        fail(*v, m.path("resolution"), "expected [width, height]");
      c.width = integer((*v)[0], m.path("resolution[0]"), 1);
      c.height = integer((*v)[1], m.path("resolution[1]"), 1);
      check(*v, m.path("resolution"), [&] { scene_checks::check_resolution(c.width, c.height); });
    }
    check(n, "camera", [&] { scene_checks::check_camera(c); });
  }

  template <class F>
  void check(const YAML::Node& n, const std::string& path, F f) const {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      fail(n, path, e.what());
    }
  }

  void lights(const YAML::Node& n) {
    if (!n.IsSequence()) fail(n, "lights", "expected a list of lights");
    for (size_t i = 0; i < n.size(); ++i) {
      Map m(*this, n[i], "lights[" + std::to_string(i) + "]", {"position", "color"});
      Light l;
      l.position = vec3(m.required("position"), m.path("position"));
      if (auto c = m.get("color")) l.color = colour(*c, m.path("color"));
      check(n[i], "lights[" + std::to_string(i) + "]", [&] { scene_checks::check_light(l); });
      scene_.lights.push_back(l);
    }
  }

  void materials(const YAML::Node& n) {
    if (!n.IsMap()) fail(n, "materials", "expected a mapping from material names to materials");
    for (auto it = n.begin(); it != n.end(); ++it) {
      if (!it->first.IsScalar())
        fail(it->first, "materials", "material names must be plain strings");
      const std::string name = it->first.Scalar();
      if (material_index_.count(name))
        fail(it->first, "materials", "duplicate material '" + name + "'");
      Map m(*this, it->second, "materials." + name,
            {"color", "ambient", "diffuse", "specular", "transmission", "ior"});
      Material mat;
      mat.name = name;
      if (auto v = m.get("color")) mat.color = colour(*v, m.path("color"));
      if (auto v = m.get("ambient")) mat.ambient = at_least(*v, m.path("ambient"), 0);
      if (auto v = m.get("diffuse")) mat.diffuse = at_least(*v, m.path("diffuse"), 0);
      if (auto v = m.get("specular")) mat.specular = at_least(*v, m.path("specular"), 0);
      if (auto v = m.get("transmission"))
        mat.transmission = at_least(*v, m.path("transmission"), 0);
      if (auto v = m.get("ior")) mat.ior = positive(*v, m.path("ior"));
      material_index_[name] = int(scene_.materials.size());
      scene_.materials.push_back(mat);
    }
  }

  void render(const YAML::Node& n) {
    // Refining hits is the machine's remedy for its own rounding (docs/numerics.md), not the
    // scene's.
    if (n.IsMap() && n["refine_hits"])
      fail(n["refine_hits"], "render.refine_hits",
           "not a scene setting: the machine key hit_refine (none or newton) chooses it, e.g. "
           "--set hit_refine=none");
    Map m(*this, n, "render", {"threshold", "max_depth", "grid", "spawn_offset", "spawn_policy"});
    if (auto v = m.get("threshold")) {
      scene_.threshold = number(*v, m.path("threshold"));
      if (!scene_checks::kThresholdRange.contains(scene_.threshold))
        fail(*v, m.path("threshold"),
             "must be in " + scene_checks::kThresholdRange.text() + ", got " +
                 str(scene_.threshold));
    }
    if (auto v = m.get("max_depth")) {
      scene_.max_depth = integer(*v, m.path("max_depth"), 1);
      check(*v, m.path("max_depth"), [&] { scene_checks::check_max_depth(scene_.max_depth); });
    }
    if (auto v = m.get("spawn_offset"))
      scene_.spawn_offset =
          at_least(*v, m.path("spawn_offset"), scene_checks::kSpawnOffsetRange.lo);
    if (auto v = m.get("spawn_policy"))
      check(*v, m.path("spawn_policy"),
            [&] { scene_.spawn_policy = parse_spawn_policy(text(*v, m.path("spawn_policy"))); });
    if (auto v = m.get("grid")) {
      if (v->IsScalar() && v->Scalar() == "auto") {
        scene_.grid.resolution = {0, 0, 0};
      } else {
        if (!v->IsSequence() || v->size() != 3)
          fail(*v, m.path("grid"), "expected 'auto' or [nx, ny, nz]");
        for (int i = 0; i < 3; ++i)
          scene_.grid.resolution[i] =
              integer((*v)[i], m.path("grid[" + std::to_string(i) + "]"), 1);
        check(*v, m.path("grid"), [&] { scene_checks::check_grid(scene_.grid); });
      }
    }
  }

  void primitives(const YAML::Node& n) {
    if (!n.IsSequence()) fail(n, "primitives", "expected a list of primitives");
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string path = "primitives[" + std::to_string(i) + "]";
      Map m(*this, n[i], path,
            {"sphere", "ellipsoid", "cylinder", "cone", "paraboloid", "hyperboloid", "plane",
             "polygon", "quadric", "mesh", "material"});
      if (auto mesh_node = m.get("mesh")) {
        if (m.size() != 1)
          fail(n[i], path,
               "a mesh names its material inside: {mesh: {file: ..., material: ...}}, with no "
               "other key");
        mesh(*mesh_node, path + ".mesh");
        continue;
      }
      const YAML::Node mat = m.required("material");
      if (m.size() != 2)
        fail(n[i], path, "expected exactly one shape (sphere, ellipsoid, ...) and a material");
      std::string kind;
      YAML::Node shape;
      for (auto it = n[i].begin(); it != n[i].end(); ++it) {
        if (it->first.Scalar() == "material") continue;
        kind = it->first.Scalar();
        shape = it->second;
      }
      std::vector<Primitive> ps =
          make(kind, shape, path + "." + kind);  // a concave polygon: its pieces
      const std::string name = text(mat, path + ".material");
      auto found = material_index_.find(name);
      if (found == material_index_.end())
        fail(mat, path + ".material", "unknown material '" + name + "'");
      for (Primitive& p : ps) {
        p.material = found->second;
        scene_.primitives.push_back(std::move(p));
        scene_.origins.push_back({file_, line_of(n[i])});
      }
    }
  }

  /// A mesh file's triangles, placed by scale and translation, with the file's materials or one of
  /// the scene's. The file is from the wild: its degenerate triangles are skipped unless --strict.
  void mesh(const YAML::Node& n, const std::string& path) {
    Map m(*this, n, path, {"file", "scale", "translate", "material"});
    const YAML::Node file_node = m.required("file");
    const std::string name = text(file_node, m.path("file"));
    if (name.empty()) fail(file_node, m.path("file"), "must name a mesh file");
    namespace fs = std::filesystem;
    const fs::path file =
        fs::path(name).is_absolute() ? fs::path(name) : fs::path(file_).parent_path() / name;
    MeshPlacement place;
    if (auto v = m.get("scale")) place.scale = positive(*v, m.path("scale"));
    if (auto v = m.get("translate")) place.translate = vec3(*v, m.path("translate"));
    if (auto v = m.get("material")) {
      const std::string mat = text(*v, m.path("material"));
      auto found = material_index_.find(mat);
      if (found == material_index_.end())
        fail(*v, m.path("material"), "unknown material '" + mat + "'");
      place.material = found->second;
    }
    std::string ext = file.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (!is_mesh_extension(ext))
      fail(file_node, m.path("file"),
           "'" + name +
               "' is not a mesh file Assimp reads (.obj, .ply, .gltf, .glb, .stl, .off, ...)");
    try {
      add_mesh(scene_, import_mesh(file.string(), options_), file.string(), place, options_);
    } catch (const SceneError& e) {
      fail(file_node, m.path("file"), e.what());
    }
  }

  /// Local z along `axis`; x along `x_axis` made perpendicular, or else along world x (world y
  /// when the axis is close to x), so radii [a, b, c] of an unrotated shape lie along x, y, z.
  Frame frame(const Vec3& origin, const Vec3& axis, const std::optional<YAML::Node>& x_node,
              const std::string& path) const {
    Frame f;
    f.origin = origin;
    f.ez = normalize(axis);
    Vec3 x = std::abs(f.ez.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    if (x_node) {
      x = direction(*x_node, path + ".x_axis");
      // Nearly parallel axes would leave too little of x_axis to build an orthonormal frame from.
      if (!(length(cross(normalize(x), f.ez)) > 1e-6))
        fail(*x_node, path + ".x_axis", "must not be parallel to axis");
    }
    const Vec3 ex = x - dot(x, f.ez) * f.ez;
    f.ex = normalize(ex);
    f.ey = cross(f.ez, f.ex);
    return f;
  }

  Vec3 axis(const Map& m) const {
    auto v = m.get("axis");
    return v ? direction(*v, m.path("axis")) : Vec3{0, 0, 1};
  }

  Aabb box(const YAML::Node& n, const std::string& path) const {
    Map m(*this, n, path, {"min", "max"});
    Aabb b{vec3(m.required("min"), m.path("min")), vec3(m.required("max"), m.path("max"))};
    if (b.empty()) fail(n, path, "min must not exceed max on any axis");
    return b;
  }

  /// The shape's primitives: one, or a concave polygon's convex pieces (geom/polygon.h). The
  /// native format is written by hand, so a degenerate shape is an error here, not skipped.
  std::vector<Primitive> make(const std::string& kind, const YAML::Node& n,
                              const std::string& path) const {
    try {
      if (kind == "polygon") return make_polygon_pieces(polygon_vertices(n, path));
      return {make_shape(kind, n, path)};
    } catch (const std::invalid_argument& e) {
      fail(n, path, e.what());
    }
  }

  std::vector<Vec3> polygon_vertices(const YAML::Node& n, const std::string& path) const {
    Map m(*this, n, path, {"vertices"});
    const YAML::Node vs = m.required("vertices");
    if (!vs.IsSequence() || vs.size() < 3)
      fail(vs, m.path("vertices"), "expected a list of at least 3 [x, y, z] vertices");
    std::vector<Vec3> v;
    for (size_t i = 0; i < vs.size(); ++i)
      v.push_back(vec3(vs[i], m.path("vertices[" + std::to_string(i) + "]")));
    return v;
  }

  Primitive make_shape(const std::string& kind, const YAML::Node& n,
                       const std::string& path) const {
    if (kind == "sphere") {
      Map m(*this, n, path, {"center", "radius"});
      return make_sphere(vec3(m.required("center"), m.path("center")),
                         positive(m.required("radius"), m.path("radius")));
    }
    if (kind == "ellipsoid") {
      Map m(*this, n, path, {"center", "radii", "axis", "x_axis"});
      const Vec3 c = vec3(m.required("center"), m.path("center"));
      const YAML::Node rn = m.required("radii");
      const Vec3 r = vec3(rn, m.path("radii"));
      if (!(r.x > 0 && r.y > 0 && r.z > 0)) fail(rn, m.path("radii"), "radii must all be > 0");
      return make_ellipsoid(frame(c, axis(m), m.get("x_axis"), path), r);
    }
    if (kind == "cylinder") {
      Map m(*this, n, path, {"base", "apex", "radius"});
      const double r = positive(m.required("radius"), m.path("radius"));
      return make_cone(vec3(m.required("base"), m.path("base")), r,
                       vec3(m.required("apex"), m.path("apex")), r);
    }
    if (kind == "cone") {
      Map m(*this, n, path, {"base", "base_radius", "apex", "apex_radius"});
      const double r0 = at_least(m.required("base_radius"), m.path("base_radius"), 0);
      const double r1 = at_least(m.required("apex_radius"), m.path("apex_radius"), 0);
      return make_cone(vec3(m.required("base"), m.path("base")), r0,
                       vec3(m.required("apex"), m.path("apex")), r1);
    }
    if (kind == "paraboloid") {
      Map m(*this, n, path, {"vertex", "axis", "k", "height"});
      const Vec3 v = vec3(m.required("vertex"), m.path("vertex"));
      const double k = positive(m.required("k"), m.path("k"));
      const double h = positive(m.required("height"), m.path("height"));
      return make_paraboloid(frame(v, axis(m), std::nullopt, path), k, h);
    }
    if (kind == "hyperboloid") {
      Map m(*this, n, path, {"center", "axis", "a", "c", "half_height", "sheets"});
      const Vec3 o = vec3(m.required("center"), m.path("center"));
      const double a = positive(m.required("a"), m.path("a"));
      const double c = positive(m.required("c"), m.path("c"));
      const double h = positive(m.required("half_height"), m.path("half_height"));
      int sheets = 1;
      if (auto s = m.get("sheets")) {
        sheets = integer(*s, m.path("sheets"), 1);
        if (sheets > 2) fail(*s, m.path("sheets"), "must be 1 or 2");
      }
      const Frame f = frame(o, axis(m), std::nullopt, path);
      return sheets == 1 ? make_hyperboloid1(f, a, c, h) : make_hyperboloid2(f, a, c, h);
    }
    if (kind == "plane") {
      Map m(*this, n, path, {"normal", "d", "box"});
      const Vec3 nrm = direction(m.required("normal"), m.path("normal"));
      const double d = m.get("d") ? number(*m.get("d"), m.path("d")) : 0.0;
      return make_plane(nrm, d, box(m.required("box"), m.path("box")));
    }
    // Only "quadric" is left: Map has rejected every other key.
    Map m(*this, n, path, {"coefficients", "box", "clip"});
    const auto c = numbers(m.required("coefficients"), m.path("coefficients"), 10,
                           "[A, B, C, D, E, F, G, H, I, J]");
    std::array<double, 10> coef;
    std::copy(c.begin(), c.end(), coef.begin());
    std::vector<HalfSpace> clips;
    if (auto cl = m.get("clip")) {
      if (!cl->IsSequence())
        fail(*cl, m.path("clip"), "expected a list of [nx, ny, nz, d] half-spaces");
      for (size_t i = 0; i < cl->size(); ++i) {
        const std::string p = m.path("clip[" + std::to_string(i) + "]");
        const auto h = numbers((*cl)[i], p, 4, "[nx, ny, nz, d]");
        if (h[0] == 0 && h[1] == 0 && h[2] == 0)
          fail((*cl)[i], p, "half-space normal must not be zero");
        clips.push_back({{h[0], h[1], h[2]}, h[3]});
      }
    }
    return make_raw_quadric(coef, box(m.required("box"), m.path("box")), clips);
  }

  std::string file_;
  SceneReadOptions options_;
  Scene scene_;
  std::map<std::string, int> material_index_;
};

}  // namespace

void override_camera(Camera& camera, const std::string& text) {
  NativeParser p("--camera", {});
  camera = p.camera_override(text, camera);
}

Scene parse_native(const std::string& text, const std::string& file_name,
                   const SceneReadOptions& options) {
  try {
    return NativeParser(file_name, options).parse(text);
  } catch (const YAML::Exception& e) {
    // Every access is type-checked first, so this is only a safety net.
    throw SceneError(file_name, e.mark.is_null() ? 0 : e.mark.line + 1,
                     std::string("YAML error: ") + e.msg);
  }
}

}  // namespace rtm
