// A scene as the host holds it before pre-processing: camera, lights, materials, primitives.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "geom/grid.h"
#include "geom/numerics.h"
#include "geom/quadric.h"
#include "scene/file_error.h"

namespace rtm {

struct Camera {
  Vec3 eye{0, 0, 10};
  Vec3 look_at{0, 0, 0};
  Vec3 up{0, 1, 0};     ///< need not be perpendicular to the view direction
  double fov_deg = 45;  ///< full horizontal angle, edge to edge (NFF `angle`)
  int width = 512, height = 512;
};

struct Light {
  Vec3 position;
  Vec3 color{1, 1, 1};
};

/// The paper's optical coefficients. Brightness semantics are in render/shade.h.
struct Material {
  std::string name;
  Vec3 color{1, 1, 1};
  double ambient = 0.1;     ///< ka: scales the ambient light
  double diffuse = 0.9;     ///< kd: scales shadow-ray brightness
  double specular = 0;      ///< ks: contribution of the reflected ray
  double transmission = 0;  ///< kt: contribution of the transmitted ray
  double ior = 1;           ///< index of refraction (inside / outside)
};

/// Where each primitive came from, for messages: file and line.
struct SourceLocation {
  std::string file;
  int line = 0;
};

/// Records a reader left out, one entry per kind (docs/scene-format.md, "Skipped records").
struct SkippedRecords {
  std::string kind;    ///< what was skipped: "degenerate 'pp'", "unknown record 'tex'"
  std::string reason;  ///< why, for the first of them ("polygon has zero area")
  int count = 0;
  std::vector<int> lines;  ///< the lines of the first few (kSkippedLinesKept)
};
constexpr size_t kSkippedLinesKept = 5;

/// How a reader treats what it cannot render.
struct SceneReadOptions {
  /// Degenerate shapes (zero area, radius or length) are errors instead of skipped records.
  bool strict = false;
  /// Unknown NFF records are skipped with a warning instead of being errors.
  bool skip_unknown = false;
  /// A mesh file's import (scene/mesh.h, import_mesh) may use this much more address space than
  /// rtm had when it began, and this long: a file that makes Assimp exhaust memory or hang is an
  /// error naming the file.
  uint64_t import_memory = uint64_t(4) << 30;
  double import_seconds = 120;
  /// Hears how a mesh file's import ("mesh import (Assimp)") and its triangles ("mesh load") go.
  StepProgress progress = nullptr;
};

/// How a spawned ray's origin is moved off the surface (render/shade.h, docs/numerics.md).
enum class SpawnPolicy {
  Relative,  ///< spawn_offset × max(1, |p|∞)
  Bound,  ///< spawn_offset × (|p|∞ + the primitive's local rounding scale at p): an error bound
};
const char* to_string(SpawnPolicy p);
/// Parses "relative" or "bound"; throws std::invalid_argument naming the choices.
SpawnPolicy parse_spawn_policy(const std::string& text);

struct Scene {
  std::string name = "scene";
  Camera camera;
  Vec3 background{0, 0, 0};
  Vec3 ambient_light{0.1, 0.1, 0.1};
  std::vector<Light> lights;
  std::vector<Material> materials;
  std::vector<Primitive>
      primitives;  ///< numbered in file order; Primitive::material indexes materials
  std::vector<SourceLocation> origins;  ///< one per primitive
  std::vector<SkippedRecords> skipped;  ///< what the reader left out, in order of first appearance
  double threshold = 0;                 ///< branch rays with contribution <= threshold are dropped
  int max_depth = 5;                    ///< primary rays are depth 1
  /// Spawned rays start this far off the surface, relative to max(1, |hit point|∞) (spawn_policy
  /// relative) or to an error bound of the hit point (bound).
  double spawn_offset = 1e-5;
  SpawnPolicy spawn_policy = SpawnPolicy::Relative;
  /// How shading lights triangles with vertex normals: the machine's normal_interpolation key,
  /// which rtm render copies here so that the reference does the same.
  NormalInterpolation normal_interpolation = kDefaultNormalInterpolation;
  GridOptions grid;
};

/// A scene file problem: the message reads "file:line: what is wrong".
struct SceneError : FileError {
  using FileError::FileError;
};

/// Reads a scene by extension: `.nff` for NFF, `.yaml`/`.yml` for the native format, any other
/// extension Assimp reads (`.obj`, `.ply`, `.gltf`, `.glb`, `.stl`, `.off`, ...) as a mesh file.
Scene load_scene(const std::string& path, const SceneReadOptions& options = {});
/// NFF text (classic semantics; see docs/scene-format.md for the mapping to the paper's
/// coefficients).
Scene parse_nff(const std::string& text, const std::string& file_name,
                const SceneReadOptions& options = {});
/// One warning line per kind of skipped record, "file:line: skipped ...", for the command line.
std::vector<std::string> skipped_warnings(const Scene& s, const std::string& file);
/// Native YAML text (docs/scene-format.md). A `mesh` entry's file is read relative to file_name's
/// folder, with `options`' import limits.
Scene parse_native(const std::string& text, const std::string& file_name,
                   const SceneReadOptions& options = {});
/// Applies `text`, a YAML mapping with any of the native format's camera keys (`{eye: [0, 2, 10],
/// fov: 30}`), to `camera`; the keys not given stay. Throws SceneError (file "--camera").
void override_camera(Camera& camera, const std::string& text);
/// The built-in default scene (every quadric kind, diffuse, reflective and transparent materials).
Scene default_scene();

/// Overrides the resolution, keeping the horizontal field of view. Throws on a zero-area image.
void set_resolution(Scene& s, int width, int height);
/// Checks a whole scene (camera, lights, materials, primitives); throws std::invalid_argument.
void validate(const Scene& s);

}  // namespace rtm
