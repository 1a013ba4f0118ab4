// What `rtm render`'s options do: the scene overrides, the machine configuration and simulation
// options they build, and the usage errors they can be.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include "cost/technology.h"
#include "machine/machine.h"
#include "options.h"
#include "scene/scene.h"

namespace rtm {

/// A mistake on the command line (exit code 2), not a failure of the run.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Runs a command and turns what it throws into rtm's message on stderr and its exit code: 2 for a
/// bad command line or configuration (UsageError, MachineLimitError), 1 for any other failure.
int run_command(const std::function<int()>& body);

/// An output that cannot be written is a bad command line, found before the work rather than
/// after it: throws UsageError naming the option. Creates the file's folder, as writing it would.
void check_writable(const char* option, const std::string& path);
/// Applies --size (WxH, or N for NxN) to a loaded scene.
void apply_size(const std::string& size, Scene& scene);
/// Applies the scene overrides (size, grid, threshold, depth, spawning) to a loaded scene.
void apply_scene_options(const RenderOptions& opt, Scene& scene);
/// The preset, then the configuration file, then --set, then the dedicated flags; validated.
MachineConfig machine_config(const RenderOptions& opt);
/// The technology `spec` names (the `tech` key's value); a bad file is a UsageError (exit 2).
Technology technology(const std::string& spec);
/// The waveform and progress options, checked against the configuration's PEs.
MachineOptions machine_options(const RenderOptions& opt, const MachineConfig& c);

}  // namespace rtm
