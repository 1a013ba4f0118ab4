// The error map (`rtm render --error-map FILE.exr`): what error/error_causes.h found, per pixel,
// as channels a script reads and as a picture a person looks at.
#pragma once

#include "error/error_causes.h"
#include "render/image_io.h"

namespace rtm {

/// Channels generation, kind, cause, primitive, reference_primitive (the PixelCause fields;
/// kind is the RayKind's number, cause the ErrorCause's). A pixel that does not differ has
/// generation 0, kind -1, cause 0 and no primitives (-1).
Channels error_map_channels(const ErrorCauses& e);

/// The colour a cause is drawn in (docs/numerics.md has the legend).
Vec3 cause_colour(ErrorCause c);

/// The machine's image dimmed to 40 % of its grey, each differing pixel in its cause's colour.
Image error_map_picture(const ErrorCauses& e, const Image& machine);

}  // namespace rtm
