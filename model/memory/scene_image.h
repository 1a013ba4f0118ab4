// The scene data the host sends every PE (paper §3.1: primitives, voxel data, lights), in the
// machine's precision.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "config/config.h"
#include "render/scene_memory.h"

namespace rtm {

struct SceneImage {
  const Scene* scene = nullptr;
  const Grid* grid = nullptr;
  std::optional<SceneMemory<float>> mem32;   ///< precision = fp32 only
  std::optional<SceneMemory<double>> mem64;  ///< precision = fp64 only
  // The bytes of each part of a PE's copy (model/memory/scene_image.cpp says what each holds).
  uint64_t primitive_bytes = 0;
  std::vector<uint32_t> primitive_record_bytes;  ///< each primitive's share of primitive_bytes
  uint64_t voxel_bytes = 0;
  uint64_t light_bytes = 0;  ///< lights and materials
  uint64_t bytes = 0;        ///< the whole copy: the size the transfer is timed by

  SceneImage(const Scene& s, const Grid& g, const MachineConfig& c);

  /// Calls f with the scene memory in the precision in use.
  template <class F>
  decltype(auto) visit(F&& f) const {
    return mem32 ? f(*mem32) : f(*mem64);
  }
};

}  // namespace rtm
