// The fuzz targets' entry functions (docs/reliability.md, "Fuzzing"). Each reads one input through
// the reader the program uses and returns whether it was read (true) or refused with that reader's
// own error (false); anything else escapes to the caller: another exception, a crash or a sanitizer
// report is a finding. The libFuzzer targets (*_fuzz.cpp, built by scripts/fuzz) and the suite's
// replay of the committed corpus (corpus_test.cpp, tb/fuzz-corpus/TARGET) call the same functions.
#pragma once

#include <string_view>

namespace rtm::fuzz {

/// An NFF scene, as `rtm render scene.nff` reads it, and again with --strict --skip-unknown.
bool nff(std::string_view input);
/// A native YAML scene, as `rtm render scene.yaml` reads it.
bool native(std::string_view input);
/// What a mesh file's import sends rtm (scene/mesh.h, encode_mesh): decoded, made a scene as
/// `rtm render model.obj` makes it, and placed in a YAML scene, with and without --strict.
bool mesh(std::string_view input);
/// A `--config` file; one that is accepted must read back from what `rtm config` prints of it.
bool config(std::string_view input);
/// One `--set KEY=VALUE` argument a line, applied in order, then the whole configuration checked.
bool set(std::string_view input);

struct Target {
  const char* name;  ///< scripts/fuzz's name, and the folder under tb/fuzz-corpus
  bool (*run)(std::string_view);
};
inline constexpr Target kTargets[] = {
    {"nff", nff}, {"native", native}, {"mesh", mesh}, {"config", config}, {"set", set}};

}  // namespace rtm::fuzz
