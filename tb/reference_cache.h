// The reference image every model render is compared against, cached on disk so sweeps and
// repeated renders pay for it once.
#pragma once

#include <cstdint>
#include <string>

#include "render/reference.h"

namespace rtm {

/// Key: the scene's text, every setting the reference depends on, and this build of the program.
/// Cache folder: $RTM_CACHE_DIR, else $XDG_CACHE_HOME/rtm, else ~/.cache/rtm; unusable: no cache.
/// `hit` tells whether the result came from the cache.
/// Every entry carries the digest of its key and a checksum of its contents; an entry that is
/// damaged, truncated or made for another key is reported on stderr once, deleted and rendered
/// again. Writers write a temporary of their own and rename it, so concurrent runs are safe. After
/// each store the least recently used entries go until the cache holds at most $RTM_CACHE_SIZE
/// (default kDefaultCacheCap), and temporaries left by writers that are gone are removed. A
/// render the watch stops (render_reference) is not stored.
ReferenceResult cached_reference(const Scene& s, const Grid& g, const std::string& scene_text,
                                 bool* hit, const ReferenceWatch& watch, PeFrame frame);

constexpr uint64_t kDefaultCacheCap = uint64_t(2) << 30;  ///< 2 GiB: about 1100 entries of 256x256

/// `rtm cache info` (where, how many entries, how large, the cap, partial files) or `rtm cache
/// clean` (removes every entry and every abandoned partial file); returns the exit code.
int run_cache(const std::string& action);

}  // namespace rtm
