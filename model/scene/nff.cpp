// NFF (Eric Haines' Neutral File Format) reader. Mapping to the paper's coefficients:
// docs/scene-format.md.
#include <charconv>
#include <climits>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string_view>

#include "geom/polygon.h"
#include "scene/scene.h"
#include "scene/scene_checks.h"

namespace rtm {

namespace {

struct Token {
  std::string_view text;
  int line;
};

// SPD writes `c` on one line where the NFF text shows three, so records are read by tokens;
// lines are kept only for messages.
std::vector<Token> tokenize(const std::string& text, int* last_line) {
  std::vector<Token> out;
  int line = 1;
  size_t i = 0;
  const size_t n = text.size();
  auto space = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
  };
  while (i < n) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (space(c)) {
      ++i;
    } else if (c == '#') {
      while (i < n && text[i] != '\n') ++i;
    } else {
      const size_t start = i;
      while (i < n && !space(text[i]) && text[i] != '#') ++i;
      out.push_back({std::string_view(text).substr(start, i - start), line});
    }
  }
  *last_line = line;
  return out;
}

/// A token for a message: printable, and short, so binary garbage cannot flood the terminal.
std::string quote(std::string_view t) {
  std::string s = "'";
  for (size_t i = 0; i < t.size() && i < 40; ++i) {
    const unsigned char c = t[i];
    s += (c >= 32 && c < 127) ? char(c) : '?';
  }
  if (t.size() > 40) s += "...";
  return s + "'";
}

enum class Num { Ok, NotNumber, OutOfRange, NotFinite };

Num to_number(std::string_view t, double* x) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);  // from_chars rejects a leading '+'
  const auto r = std::from_chars(t.data(), t.data() + t.size(), *x);
  if (r.ec == std::errc::result_out_of_range) return Num::OutOfRange;
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) return Num::NotNumber;
  return std::isfinite(*x) ? Num::Ok : Num::NotFinite;
}

bool is_number(std::string_view t) {
  double x;
  return to_number(t, &x) != Num::NotNumber;
}

std::string str(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

constexpr std::string_view kViewKeys[] = {"from", "at", "up", "angle", "hither", "resolution"};
constexpr std::string_view kRecordKeys[] = {"v", "b", "l", "f", "s", "c", "p", "pp"};

bool is_keyword(std::string_view t) {
  for (std::string_view k : kViewKeys)
    if (t == k) return true;
  for (std::string_view k : kRecordKeys)
    if (t == k) return true;
  return false;
}

class NffParser {
 public:
  NffParser(const std::string& text, const std::string& file, const SceneReadOptions& options)
      : file_(file), options_(options) {
    tokens_ = tokenize(text, &last_line_);
  }

  Scene parse() {
    scene_.name = std::filesystem::path(file_).stem().string();
    scene_.threshold = 0;  // SPD rules: no adaptive depth cutoff, depth 5
    scene_.max_depth = 5;
    while (pos_ < tokens_.size()) record(tokens_[pos_++]);
    if (view_line_ == 0)
      fail(last_line_,
           "no view block: an NFF file needs 'v' followed by from/at/up/angle/hither/resolution");
    finish_lights();
    try {
      validate(scene_);
    } catch (const std::invalid_argument& e) {
      fail(last_line_, e.what());  // unreachable if the per-record checks are complete
    }
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(int line, const std::string& what) const {
    throw SceneError(file_, line, what);
  }

  void record(const Token& kw) {
    const std::string_view k = kw.text;
    if (k == "v") return view(kw);
    if (k == "b") {
      scene_.background = vec3(kw, "background colour (R G B)");
      return check(kw, [&] { scene_checks::check_colour(scene_.background, "background colour"); });
    }
    if (k == "l") return light(kw);
    if (k == "f") return material(kw);
    if (k == "s") return sphere(kw);
    if (k == "c") return cone(kw);
    if (k == "p") return polygon(kw, false);
    if (k == "pp") return polygon(kw, true);
    for (std::string_view v : kViewKeys)
      if (k == v) fail(kw.line, quote(k) + " outside the view block (it must follow 'v')");
    if (is_number(k))
      fail(kw.line, "unexpected number " + quote(k) +
                        " (expected a keyword; too many numbers in the record above?)");
    if (options_.skip_unknown) return skip_unknown(kw);
    fail(kw.line,
         "unknown keyword " + quote(k) + " (--skip-unknown skips records rtm does not know)");
  }

  /// An unknown record: its keyword, the rest of its line up to a known keyword (file names and
  /// words included), then every number that follows (continuation lines such as the vertex
  /// lines of a polygon-like record). The first word on a later line starts the next record.
  void skip_unknown(const Token& kw) {
    while (pos_ < tokens_.size() && tokens_[pos_].line == kw.line &&
           !is_keyword(tokens_[pos_].text))
      ++pos_;
    while (pos_ < tokens_.size() && is_number(tokens_[pos_].text)) ++pos_;
    note_skipped("unknown " + quote(kw.text), "not an NFF record", kw.line);
  }

  void note_skipped(const std::string& kind, const std::string& reason, int line) {
    for (SkippedRecords& k : scene_.skipped)
      if (k.kind == kind) {
        ++k.count;
        if (k.lines.size() < kSkippedLinesKept) k.lines.push_back(line);
        return;
      }
    scene_.skipped.push_back({kind, reason, 1, {line}});
  }

  template <class F>
  void check(const Token& kw, F f) const {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      fail(kw.line, std::string(kw.text) + ": " + e.what());
    }
  }

  /// The next token as a number for record `kw`, whose numbers are laid out as `layout`;
  /// `index` numbers of it have been read.
  double number(const Token& kw, const std::string& layout, int index) {
    if (pos_ >= tokens_.size())
      fail(kw.line, "'" + std::string(kw.text) + "' record ends early: expected " + layout);
    const Token& t = tokens_[pos_];
    double x;
    switch (to_number(t.text, &x)) {
      case Num::Ok:
        ++pos_;
        return x;
      case Num::OutOfRange:
        fail(t.line, "number " + quote(t.text) + " is out of range");
      case Num::NotFinite:
        fail(t.line, "number " + quote(t.text) + " is not finite");
      case Num::NotNumber:
        break;
    }
    // A record cut short runs into the next keyword: report it against the record.
    if (is_keyword(t.text))
      fail(kw.line, "'" + std::string(kw.text) + "' record has too few numbers: expected " +
                        layout + ", found " + std::to_string(index) + " before " + quote(t.text));
    fail(t.line, quote(t.text) + " is not a number (expected " + layout + " after '" +
                     std::string(kw.text) + "')");
  }

  Vec3 vec3(const Token& kw, const std::string& layout, int first = 0) {
    const double x = number(kw, layout, first);
    const double y = number(kw, layout, first + 1);
    const double z = number(kw, layout, first + 2);
    return {x, y, z};
  }

  int integer(const Token& kw, const std::string& layout, int index, int lo) {
    const size_t at = pos_;
    const double x = number(kw, layout, index);
    if (x != std::floor(x) || x < lo || x > INT_MAX)
      fail(tokens_[at].line, "'" + std::string(kw.text) + "': " + quote(tokens_[at].text) +
                                 " must be a whole number >= " + std::to_string(lo));
    return int(x);
  }

  void view(const Token& v) {
    if (view_line_ != 0)
      fail(v.line, "second view block ('v'); the first is on line " + std::to_string(view_line_));
    view_line_ = v.line;
    Camera& cam = scene_.camera;
    bool seen[6] = {};
    int lines[6] = {};
    for (int i = 0; i < 6; ++i) {
      if (pos_ >= tokens_.size()) fail(v.line, "view block ends early: missing " + missing(seen));
      const Token& kw = tokens_[pos_];
      int which = -1;
      for (int j = 0; j < 6; ++j)
        if (kw.text == kViewKeys[j]) which = j;
      if (which < 0)
        fail(kw.line, "view block: expected " + missing(seen) + ", got " + quote(kw.text));
      if (seen[which]) fail(kw.line, "view block: " + quote(kw.text) + " given twice");
      seen[which] = true;
      lines[which] = kw.line;
      ++pos_;
      switch (which) {
        case 0:
          cam.eye = vec3(kw, "x y z");
          break;
        case 1:
          cam.look_at = vec3(kw, "x y z");
          break;
        case 2:
          cam.up = vec3(kw, "x y z");
          break;
        case 3:
          cam.fov_deg = number(kw, "an angle in degrees", 0);
          if (!(cam.fov_deg > 0 && cam.fov_deg < 180))
            fail(kw.line, "angle must be in (0, 180) degrees, got " + str(cam.fov_deg));
          break;
        case 4:
          number(kw, "a distance", 0);
          break;  // near clipping: meaningless for a ray tracer
        case 5:
          cam.width = integer(kw, "xres yres", 0, 1);
          cam.height = integer(kw, "xres yres", 1, 1);
          check(kw, [&] { scene_checks::check_resolution(cam.width, cam.height); });
          break;
      }
    }
    camera_lines(cam, lines);
    check(v, [&] { scene_checks::check_camera(cam); });
  }

  /// The camera problems that one record causes, reported at that record's line (the rest of
  /// check_camera's at the `v` line).
  void camera_lines(const Camera& cam, const int* lines) const {
    const int from = lines[0], at = lines[1], up = lines[2];
    if (max_abs(cam.eye) > kMaxCoordinate)
      fail(from, "'from' must be within +-1e150 of the origin");
    if (max_abs(cam.look_at) > kMaxCoordinate)
      fail(at, "'at' must be within +-1e150 of the origin");
    const Vec3 dir = cam.look_at - cam.eye;
    if (length(dir) == 0)
      fail(at, "'at' is the same point as 'from' (line " + std::to_string(from) +
                   "): the camera has no view direction");
    if (!std::isfinite(length(dir)))
      fail(at, "'at' is too far from 'from' (line " + std::to_string(from) + ")");
    if (length(cam.up) == 0) fail(up, "camera up vector is zero");
    if (!std::isfinite(length(cam.up))) fail(up, "camera up vector is too long");
    if (!(length(cross(normalize(dir), normalize(cam.up))) > 1e-9))
      fail(up, "camera up vector is parallel to the view direction (from line " +
                   std::to_string(from) + " to at line " + std::to_string(at) + ")");
  }

  static std::string missing(const bool* seen) {
    std::string s;
    for (int j = 0; j < 6; ++j)
      if (!seen[j]) s += (s.empty() ? "'" : ", '") + std::string(kViewKeys[j]) + "'";
    return s;
  }

  void light(const Token& kw) {
    Light l;
    l.position = vec3(kw, "X Y Z [R G B]");
    // The colour is optional: it is there exactly when numbers follow.
    if (pos_ < tokens_.size() && is_number(tokens_[pos_].text))
      l.color = vec3(kw, "X Y Z [R G B]", 3);
    check(kw, [&] { scene_checks::check_light(l); });
    scene_.lights.push_back(l);
  }

  void material(const Token& kw) {
    const char* layout = "R G B Kd Ks Shine T ior";
    Material m;
    m.name = "f@" + std::to_string(kw.line);
    m.color = vec3(kw, layout);
    m.diffuse = number(kw, layout, 3);
    m.ambient = m.diffuse;  // NFF has no ambient coefficient
    m.specular = number(kw, layout, 4);
    number(kw, layout, 5);  // Shine: the paper has no highlight term
    m.transmission = number(kw, layout, 6);
    const double ior = number(kw, layout, 7);
    m.ior = ior > 0 ? ior : 1;  // SPD writes 0 for opaque surfaces
    check(kw, [&] { scene_checks::check_material(m); });
    scene_.materials.push_back(m);
  }

  void need_material(const Token& kw) const {
    if (scene_.materials.empty())
      fail(kw.line, "'" + std::string(kw.text) + "' before any 'f' material record");
  }

  /// Adds the primitives `make` returns (one, or a polygon's convex pieces). A degenerate shape
  /// is skipped and counted, or with strict reading an error.
  template <class Make>
  void add(const Token& kw, Make make) {
    std::vector<Primitive> ps;
    try {
      ps = make();
    } catch (const DegenerateShape& e) {
      if (options_.strict) fail(kw.line, std::string(kw.text) + ": " + e.what() + " (--strict)");
      note_skipped("degenerate " + quote(kw.text), e.what(), kw.line);
      return;
    } catch (const std::invalid_argument& e) {
      fail(kw.line, std::string(kw.text) + ": " + e.what());
    }
    for (Primitive& p : ps) {
      p.material = int(scene_.materials.size()) - 1;
      scene_.primitives.push_back(std::move(p));
      scene_.origins.push_back({file_, kw.line});
    }
  }

  void sphere(const Token& kw) {
    need_material(kw);
    const Vec3 c = vec3(kw, "x y z radius");
    const double r = number(kw, "x y z radius", 3);
    add(kw, [&] {
      return std::vector<Primitive>{make_sphere(c, std::abs(r))};
    });  // negative: inside visible only; same surface
  }

  void cone(const Token& kw) {
    need_material(kw);
    const char* layout = "base_x base_y base_z base_radius apex_x apex_y apex_z apex_radius";
    const Vec3 base = vec3(kw, layout);
    const double br = number(kw, layout, 3);
    const Vec3 apex = vec3(kw, layout, 4);
    const double ar = number(kw, layout, 7);
    add(kw, [&] { return std::vector<Primitive>{make_cone(base, br, apex, ar)}; });
  }

  void polygon(const Token& kw, bool patch) {
    need_material(kw);
    const int n = integer(kw, "a vertex count (at least 3)", 0, 3);
    const std::string layout = std::string(patch ? "x y z nx ny nz" : "x y z") + " for each of " +
                               std::to_string(n) + " vertices";
    const int per = patch ? 6 : 3;
    std::vector<Vec3> v, normals;
    for (int i = 0; i < n; ++i) {
      v.push_back(vec3(kw, layout, i * per));
      if (patch) normals.push_back(vec3(kw, layout, i * per + 3));
    }
    add(kw, [&] {
      std::vector<Primitive> ps = make_polygon_pieces(v);
      // A triangle's vertex normals, for smooth shading (docs/scene-format.md, "Vertex normals").
      if (patch && n == 3 && ps.size() == 1) {
        ps[0].normals = vertex_normals(ps[0], normals);
        if (ps[0].normals.empty())
          note_skipped(quote(kw.text) + " vertex normal", kFlatNormalsReason, kw.line);
      }
      return ps;
    });
  }

  void finish_lights() {
    // SPD's suggestion: each light, and the ambient term, at sqrt(L)/(2L). With no lights the
    // ambient light is left at full white, so the scene is not black.
    const size_t L = scene_.lights.size();
    const double intensity = L == 0 ? 1.0 : std::sqrt(double(L)) / (2.0 * double(L));
    for (Light& l : scene_.lights) l.color *= intensity;
    scene_.ambient_light = Vec3(intensity);
  }

  std::string file_;
  SceneReadOptions options_;
  std::vector<Token> tokens_;
  size_t pos_ = 0;
  int last_line_ = 1;
  int view_line_ = 0;
  Scene scene_;
};

}  // namespace

Scene parse_nff(const std::string& text, const std::string& file_name,
                const SceneReadOptions& options) {
  return NffParser(text, file_name, options).parse();
}

}  // namespace rtm
