#include "fuzz/entries.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "config/config.h"
#include "scene/mesh.h"
#include "scene/scene.h"

namespace rtm::fuzz {

namespace {

/// What the program does with a scene it has read: the skipped records' warnings, then the
/// checks it runs before rendering. A parser that accepts what validate() refuses is a finding
/// (the parsers check each record as they read it, to name its line), so that error escapes.
void use(const Scene& s, const std::string& file) {
  skipped_warnings(s, file);
  validate(s);
}

/// --strict, and --skip-unknown when `skip_unknown`.
SceneReadOptions strict_options(bool skip_unknown) {
  SceneReadOptions o;
  o.strict = true;
  o.skip_unknown = skip_unknown;
  return o;
}

}  // namespace

bool nff(std::string_view input) {
  const std::string text(input);
  bool read = true;
  for (const SceneReadOptions& options : {SceneReadOptions{}, strict_options(true)}) {
    try {
      use(parse_nff(text, "fuzz.nff", options), "fuzz.nff");
    } catch (const SceneError&) {
      read = false;
    }
  }
  return read;
}

bool native(std::string_view input) {
  try {
    use(parse_native(std::string(input), "fuzz.yaml"), "fuzz.yaml");
    return true;
  } catch (const SceneError&) {
    return false;
  }
}

bool mesh(std::string_view input) {
  MeshData m;
  try {
    m = decode_mesh(std::string(input));
  } catch (const std::invalid_argument&) {
    return false;  // what import_mesh reports as a bad answer
  }
  bool read = true;
  for (const SceneReadOptions& options : {SceneReadOptions{}, strict_options(false)}) {
    try {
      use(mesh_scene(m, "fuzz.obj", options), "fuzz.obj");
    } catch (const SceneError&) {
      read = false;
    }
    // In a YAML scene beside a sphere, placed, with the scene's own material.
    Scene s = parse_native(
        "camera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\nmaterials: {red: {}}\n"
        "primitives: [{sphere: {center: [0, 0, 0], radius: 1}, material: red}]\n",
        "fuzz.yaml");
    try {
      add_mesh(s, m, "fuzz.obj", {2, {1e3, -1, 0}, 0}, options);
      use(s, "fuzz.yaml");
    } catch (const SceneError&) {
      read = false;
    }
  }
  return read;
}

bool config(std::string_view input) {
  MachineConfig c;
  try {
    parse_config(c, std::string(input), "fuzz-config.yaml");
    c.validate();
  } catch (const ConfigError&) {
    return false;
  } catch (const std::invalid_argument&) {  // validate(): the rules across keys (rtm exits 2)
    return false;
  }
  const std::string described = describe_config(c);
  MachineConfig again;
  parse_config(again, described, "described.yaml");
  if (describe_config(again) != described)
    throw std::logic_error("what rtm config prints of an accepted file reads back differently:\n" +
                           described);
  return true;
}

bool set(std::string_view input) {
  MachineConfig c;
  try {
    for (size_t at = 0; at < input.size();) {  // a last newline ends the last line
      const size_t end = std::min(input.find('\n', at), input.size());
      set_config_assignment(c, std::string(input.substr(at, end - at)));
      at = end + 1;
    }
    c.validate();
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

}  // namespace rtm::fuzz
