#include "render/camera.h"

namespace rtm {

const char* ray_kind_name(RayKind k) {
  switch (k) {
    case RayKind::Primary:
      return "primary";
    case RayKind::Shadow:
      return "shadow";
    case RayKind::Reflected:
      return "reflected";
    case RayKind::Transmitted:
      return "transmitted";
  }
  return "?";
}

PrimaryRays::PrimaryRays(const Camera& c) : eye_(c.eye), width_(c.width), height_(c.height) {
  forward_ = normalize(c.look_at - c.eye);
  right_ = normalize(cross(forward_, c.up));
  up_ = cross(right_, forward_);  // the part of `up` perpendicular to the view direction
  half_w_ = std::tan(c.fov_deg * M_PI / 360.0);
  half_h_ = half_w_ * double(c.height) / double(c.width);
}

Ray PrimaryRays::at(int x, int y) const {
  const double sx = (2.0 * (x + 0.5) / width_ - 1.0) * half_w_;
  const double sy = (1.0 - 2.0 * (y + 0.5) / height_) * half_h_;
  Ray r;
  r.origin = eye_;
  r.dir = normalize(forward_ + sx * right_ + sy * up_);
  r.pixel = uint32_t(y) * uint32_t(width_) + uint32_t(x);
  r.kind = RayKind::Primary;
  r.depth = 1;
  r.contribution = 1;
  return r;
}

}  // namespace rtm
