// `rtm pov`: export a scene to POV-Ray 3.7 scene description language, for validating the
// reference renderer against an independent ray tracer (docs/validation-povray.md).
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace rtm {

struct Scene;

struct PovOptions {
  std::string scene;          ///< empty: the built-in default scene
  std::string size;           ///< "WxH", empty: the scene's own
  std::string out;            ///< .pov file to write
  bool id = false;            ///< flat primitive-ID colours instead of shading
  bool strict = false;        ///< degenerate shapes are errors (as `rtm render --strict`)
  bool skip_unknown = false;  ///< unknown NFF records are skipped (as `rtm render --skip-unknown`)
  std::string normal_interpolation;  ///< flat or barycentric; empty: the default preset's
};

/// The scene as POV-Ray 3.7 SDL. With `id`, each primitive is a flat colour encoding its number
/// + 1 in 24 bits (R high byte), the background is black, and there are no lights, so an 8-bit
/// image rendered with File_Gamma=1.0 and no antialiasing decodes to the primitive number.
/// Triangles with vertex normals carry them when the scene's normal_interpolation is barycentric.
std::string to_pov(const Scene& s, bool id);

/// Registers `rtm pov` on the command line; its options are stored in `opt`.
CLI::App* add_pov_command(CLI::App& app, PovOptions& opt);
/// Runs `rtm pov`; returns the process exit code.
int run_pov(const PovOptions& opt);

}  // namespace rtm
