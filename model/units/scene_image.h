// The scene data the host sends every PE (paper §3.1: primitives, voxel data, lights), in the
// machine's precision.
#pragma once

#include <cstdint>
#include <optional>

#include "machine/config.h"
#include "render/scene_memory.h"

namespace rtm {

struct SceneImage {
  const Scene* scene = nullptr;
  const Grid* grid = nullptr;
  std::optional<SceneMemory<float>> mem32;   ///< precision = fp32 only
  std::optional<SceneMemory<double>> mem64;  ///< precision = fp64 only
  uint64_t bytes = 0;  ///< the size the transfer is timed by

  SceneImage(const Scene& s, const Grid& g, const MachineConfig& c);

  /// Calls f with the scene memory in the precision in use.
  template <class F>
  decltype(auto) visit(F&& f) const {
    return mem32 ? f(*mem32) : f(*mem64);
  }
};

}  // namespace rtm
