// What a render will need in memory, estimated before it runs, and the budget it must fit in
// (rtm render --max-memory). Each part names what it holds, so a refusal can say which is too big.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config/config.h"
#include "scene/scene.h"

namespace rtm {

struct MemoryPart {
  std::string name;  ///< "images", "primary rays", ...
  double bytes = 0;
  std::string detail;  ///< how it is made up, for the message
};

/// Upper estimates of a render's memory, by part. `config` is null for --reference. The figures
/// per pixel and per PE are what this build measured (docs/reliability.md, "Memory budget").
/// What grows with the ray tree (rays waiting in the front buffers, an event log) depends on the
/// frame's data, not its size: the machine's monitor holds it to the budget as it runs.
/// `threads`: the reference's (0: every core).
std::vector<MemoryPart> estimate_memory(const Scene& s, const Grid& g, const MachineConfig* config,
                                        bool tracing, int threads);

/// The bytes a scene's primitives and their origins hold in this process, their heap blocks
/// included: a mesh of a million triangles holds about 700 MB of them.
double scene_bytes(const Scene& s);

/// The default budget: three quarters of the machine's memory, or of the process's control
/// group's limit or address-space limit where those are smaller.
uint64_t default_memory_budget();
/// Where the default comes from, for messages: "3/4 of this machine's 23.4 GiB".
std::string default_memory_budget_source();

/// Throws UsageError if the parts add up to more than `budget`, naming the total, the budget and
/// the largest part with its make-up. `given`: the budget came from --max-memory.
void check_memory_budget(const std::vector<MemoryPart>& parts, uint64_t budget, bool given);

/// The ray tree's size: at most how many rays one primary ray can grow into (its shadow rays
/// included) under the scene's max_depth and threshold, every path's contribution bounded by the
/// largest ks and kt any primitive's material has (a ray of generation d with j transmissions has
/// contribution at most ks^(d-1-j) kt^j). Infinite where it overflows a double.
double rays_per_primary_bound(const Scene& s);

}  // namespace rtm
