// What one ray did, as any renderer of the algorithm traced it: how its walk ended, what it added
// to its pixel and what it spawned. The error attribution (error/error_causes.h) compares the
// machine's and the reference's rays through this.
#pragma once

#include <cstdint>
#include <vector>

#include "render/pixel_sum.h"
#include "render/ray.h"

namespace rtm {

struct RayResult {
  enum class End : uint8_t {
    Hit,           ///< a primary or branch ray hit `prim` at t
    Missed,        ///< a primary or branch ray left the object space
    LightReached,  ///< a shadow ray reached its light
    Blocked,       ///< a shadow ray was blocked by `prim` at t
  } end = End::Missed;
  uint32_t prim = 0;
  double t = 0;
  PixelSum added;            ///< the brightness it added to its pixel, as the pixel's sum holds it
  std::vector<Ray> spawned;  ///< in the order shading spawned them
};

/// Something that traces one ray at a time: the reference renderer or a PE's units.
class RayTracer {
 public:
  virtual ~RayTracer() = default;
  virtual void trace(const Ray& ray, RayResult& out) = 0;
};

}  // namespace rtm
