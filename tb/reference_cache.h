// The reference image every model render is compared against, cached on disk so sweeps and
// repeated renders pay for it once.
#pragma once

#include <string>

#include "render/reference.h"

namespace rtm {

/// Key: the scene's text, every setting the reference depends on, and this build of the program.
/// Cache folder: $RTM_CACHE_DIR, else $XDG_CACHE_HOME/rtm, else ~/.cache/rtm; unusable: no cache.
/// `hit` tells whether the result came from the cache.
ReferenceResult cached_reference(const Scene& s, const Grid& g, const std::string& scene_text, bool* hit);

}  // namespace rtm
