// Primary-ray generation, the host's second pre-processing job.
#pragma once

#include "render/ray.h"
#include "scene/scene.h"

namespace rtm {

/// Pinhole camera with NFF semantics: rays through pixel centres, row 0 at the top, fov the full
/// horizontal angle edge to edge; the vertical extent follows the aspect ratio.
class PrimaryRays {
 public:
  explicit PrimaryRays(const Camera& c);
  Ray at(int x, int y) const;

 private:
  Vec3 eye_, forward_, right_, up_;
  double half_w_, half_h_;
  int width_, height_;
};

}  // namespace rtm
