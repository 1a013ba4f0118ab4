// A ray as it travels through the machine: small enough to sit in a FIFO.
#pragma once

#include <cstdint>
#include <limits>

#include "geom/vec.h"
#include "scene/ray_depth.h"

namespace rtm {

enum class RayKind : uint8_t { Primary, Shadow, Reflected, Transmitted };
constexpr int kRayKinds = 4;
const char* ray_kind_name(RayKind k);

struct Ray {
  Vec3 origin;               ///< V
  Vec3 dir;                  ///< U, unit length
  double t_max = kInf;       ///< shadow rays end at their light
  Vec3 brightness{0, 0, 0};  ///< shadow rays: added to the pixel if the light is reached
  double contribution = 1;   ///< product of kd / ks / kt along the ray's ancestry
  uint32_t pixel = 0;        ///< y * width + x
  uint8_t depth = 1;         ///< primary rays are generation 1
  RayKind kind = RayKind::Primary;
};

static_assert(
    std::numeric_limits<decltype(Ray::depth)>::max() == kMaxRayDepth,
    "Ray::depth holds every generation, and docs/scene-format.md and rtm render --help give 255");

}  // namespace rtm
