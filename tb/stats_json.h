// The statistics file of `rtm render` (docs/machine.md, "Statistics"): the model's figures as JSON.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cost/unit_cost.h"
#include "error/error_causes.h"
#include "machine/machine.h"
#include "render/image_io.h"
#include "render/reference.h"
#include "scene/scene.h"

namespace rtm {

/// The stats file's format version: docs/stats.schema.json describes exactly this one, and allows
/// no key it does not list, so any change to the format (a key added, gone, or changed in type or
/// meaning) raises it, with the schema in the same commit.
inline constexpr int kStatsSchemaVersion = 7;

/// What was run, at the head of every stats file: the format's version, the build that ran it
/// (tb/build_info.h), the command line as given (argv), the scene file as named there (null: the
/// built-in scene) and an FNV-1a hash of the bytes read, so that a stats file names the program
/// and the input it came from.
nlohmann::json run_json(const std::vector<std::string>& command_line, const std::string& scene_path,
                        const std::string& scene_text);

/// The head of every stats file: the scene as rendered and the grid built for it.
nlohmann::json scene_json(const Scene& s, const Grid& g, double grid_seconds);

/// The rest of a --reference render's stats file: its counts and wall time.
nlohmann::json reference_render_json(const ReferenceResult& r);

/// The rest of a machine render's stats file: the machine's figures, its error against the
/// reference, the machine's `cost` (cost/unit_cost.h), the flat `summary` (a sweep's results.csv
/// columns) and the reference's run.
nlohmann::json machine_render_json(const MachineResult& m, const MachineConfig& c,
                                   const MachineCost& cost, const ImageError& err,
                                   const ErrorCauses& causes, const ReferenceResult& ref,
                                   bool ref_cached);

}  // namespace rtm
