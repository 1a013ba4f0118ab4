// The payload that travels between the PE's stages.
#pragma once

#include <cstdint>
#include <ostream>

#include "geom/dda.h"
#include "render/ray.h"

namespace rtm {

/// A ray plus its walk through the grid. The search stage examines `walk`'s current voxel,
/// records it in `examined` for the intersection stage, and advances `walk` to the next voxel.
struct MachineRay {
  Ray ray;
  DdaState walk;         ///< the voxel to examine on the next pass
  DdaState examined;     ///< the voxel the intersection stage tests
  bool started = false;  ///< walk set up (done on the ray's first pass through a search unit)
  bool last = false;     ///< `examined` is the last voxel of the walk
  uint32_t id = 0;       ///< unique within its PE, for waveforms
  uint32_t slot = 0;     ///< the pixel's index in its PE's frame buffer
  // Set by the intersection stage for the shading stage.
  double t_hit = 0;
  uint32_t prim = 0;
  enum class Arrival : uint8_t { Hit, LightReached, Missed } arrival = Arrival::Hit;
};

inline std::ostream& operator<<(std::ostream& os, const MachineRay& r) {
  return os << "ray#" << r.id;
}

/// Sent to the front buffer when a ray leaves the loop, returning its credit.
struct RayEnd {
  uint32_t id = 0;
};
inline std::ostream& operator<<(std::ostream& os, const RayEnd& e) { return os << "end#" << e.id; }

}  // namespace rtm
