// The statistics file of `rtm render` (docs/machine.md, "Statistics"): the model's figures as JSON.
#pragma once

#include <nlohmann/json.hpp>

#include "machine/machine.h"
#include "render/image_io.h"
#include "render/reference.h"
#include "scene/scene.h"

namespace rtm {

/// The head of every stats file: the scene as rendered and the grid built for it.
nlohmann::json scene_json(const Scene& s, const Grid& g, double grid_seconds);

/// The rest of a --reference render's stats file: its counts and wall time.
nlohmann::json reference_render_json(const ReferenceResult& r);

/// The rest of a machine render's stats file: the machine's figures, its error against the
/// reference, the flat `summary` (a sweep's results.csv columns) and the reference's run.
nlohmann::json machine_render_json(const MachineResult& m, const MachineConfig& c, const ImageError& err,
                                   const ReferenceResult& ref, bool ref_cached);

}  // namespace rtm
