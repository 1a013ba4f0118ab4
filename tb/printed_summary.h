// What `rtm render` prints when it is done (not with --quiet): the run's headline figures and
// where its files went.
#pragma once

#include <string>

#include "cost/unit_cost.h"
#include "error/error_causes.h"
#include "machine/machine.h"
#include "render/image_io.h"
#include "render/reference.h"
#include "scene/scene.h"

namespace rtm {

/// The files a render wrote; empty: not written.
struct RenderFiles {
  std::string image, stats, id_map, error_map, error_picture, vcd, gtkw;
};

/// After a --reference render.
void print_reference_summary(const Scene& s, const Grid& g, double grid_seconds,
                             const ReferenceResult& r, const RenderFiles& files);

/// After a machine render, compared with the reference.
void print_machine_summary(const Scene& s, const Grid& g, double grid_seconds,
                           const MachineConfig& c, const MachineResult& m, const MachineCost& cost,
                           const ImageError& err, const ErrorCauses& causes,
                           const ReferenceResult& ref, bool ref_cached, const RenderFiles& files);

}  // namespace rtm
