// Triangle meshes: what a mesh file holds once imported (model/scene/mesh_import.cpp reads one
// through Assimp), the bytes it crosses a process boundary as, and how it becomes scene primitives
// (docs/scene-format.md, "Mesh files"). No Assimp here: what we do with its output is plain C++,
// fuzzed on its own (tb/fuzz).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace rtm {

/// A material as the file states it; each field is there only if the file sets it.
struct MeshMaterial {
  std::string name;
  std::optional<Vec3> kd, ks;    ///< OBJ/MTL Kd, Ks (and what other formats call diffuse, specular)
  std::optional<double> ns, ni;  ///< Ns (shininess), Ni (index of refraction)
  std::optional<double> opacity;   ///< d; OBJ's Tr is 1 - d
  std::optional<int> illum;        ///< OBJ's illumination model
  std::optional<Vec3> base_color;  ///< glTF metallic-roughness
  std::optional<double> metallic, roughness, transmission;
};

struct MeshCamera {
  Vec3 eye, look_at, up;
  double fov_deg = 45;  ///< full horizontal angle
};

/// A mesh file's contents, every node's transform applied: world-space triangles.
struct MeshData {
  std::vector<Vec3> positions;
  std::vector<Vec3>
      normals;  ///< one per position (zero where the file has none), or empty: none at all
  std::vector<std::array<uint32_t, 3>> triangles;  ///< indices into positions
  std::vector<uint32_t> triangle_material;         ///< one per triangle, an index into materials
  std::vector<MeshMaterial> materials;
  std::optional<MeshCamera> camera;
  std::vector<Light> lights;      ///< the file's point lights, colours as the file gives them
  uint64_t points_and_lines = 0;  ///< faces of 1 or 2 corners, which have no area to render
  uint64_t other_lights = 0;      ///< lights that are not points (directional, spot, area)
};

/// The bytes import_mesh's child process sends its parent. decode_mesh throws
/// std::invalid_argument on bytes that are not a whole encoding (sizes are checked before anything
/// is allocated, so no input makes it allocate more than the input's size allows).
std::string encode_mesh(const MeshData& m);
MeshData decode_mesh(const std::string& bytes);

/// The machine's material for a file's: the mapping docs/scene-format.md, "Materials", gives.
Material machine_material(const MeshMaterial& m);

/// Where a mesh goes in a scene: p' = scale × p + translate; `material`, an index into the scene's
/// materials, replaces the file's own.
struct MeshPlacement {
  double scale = 1;
  Vec3 translate{0, 0, 0};
  std::optional<int> material;
};

/// Adds the mesh's triangles to `s` (and its materials, unless placement overrides them), each
/// triangle a polygon primitive of `file`. A degenerate triangle (repeated corners, zero area) is
/// skipped and counted, or with options.strict an error. Throws SceneError naming `file` and the
/// triangle for an index out of range, a corner that is not finite or out of range.
void add_mesh(Scene& s, const MeshData& m, const std::string& file, const MeshPlacement& placement,
              const SceneReadOptions& options);

/// A scene of the mesh alone: its materials, its camera or a framing of its box, its point lights
/// or one default light (docs/scene-format.md, "Mesh files").
Scene mesh_scene(const MeshData& m, const std::string& file, const SceneReadOptions& options);

/// The camera that frames a box: docs/scene-format.md, "Mesh files".
Camera framing_camera(const Aabb& box);

/// Imports a mesh file through Assimp in a child process held to options' memory and time limits,
/// so that the library's crash, hang or exhaustion is a SceneError naming the file, not rtm's.
MeshData import_mesh(const std::string& path, const SceneReadOptions& options);
/// Whether the import's child runs under SceneReadOptions::import_memory: not in sanitizer
/// builds, whose shadow memory no address-space limit admits (the time limit still holds).
bool import_memory_is_limited();
/// Does Assimp read files with this extension (".obj", lower case, with the dot)?
bool is_mesh_extension(const std::string& ext);

}  // namespace rtm
