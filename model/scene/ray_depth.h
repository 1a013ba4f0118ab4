// The deepest generation a ray can have: what a ray's depth field holds (render/ray.h checks it).
// A scene's max_depth is checked against it (scene/scene.cpp), so a child's depth + 1 never wraps
// round to 0.
#pragma once

namespace rtm {

constexpr int kMaxRayDepth = 255;

}  // namespace rtm
