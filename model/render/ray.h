// A ray as it travels through the machine: small enough to sit in a FIFO.
#pragma once

#include <cstdint>
#include <limits>

#include "geom/vec.h"

namespace rtm {

enum class RayKind : uint8_t { Primary, Shadow, Reflected, Transmitted };
constexpr int kRayKinds = 4;
const char* ray_kind_name(RayKind k);

struct Ray {
  Vec3 origin;             ///< V
  Vec3 dir;                ///< U, unit length
  double t_max = kInf;     ///< shadow rays end at their light
  Vec3 brightness{0, 0, 0};  ///< shadow rays: added to the pixel if the light is reached
  double contribution = 1;   ///< product of kd / ks / kt along the ray's ancestry
  uint32_t pixel = 0;        ///< y * width + x
  uint8_t depth = 1;         ///< primary rays are generation 1
  RayKind kind = RayKind::Primary;
};

/// The deepest generation a ray can have: what Ray::depth holds. A scene's max_depth is checked
/// against it (scene/scene.cpp), so a child's depth + 1 never wraps round to 0.
constexpr int kMaxRayDepth = std::numeric_limits<decltype(Ray::depth)>::max();
static_assert(kMaxRayDepth == 255, "docs/scene-format.md and rtm render --help give 255");

}  // namespace rtm
