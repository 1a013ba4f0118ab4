#include "error/error_map.h"

#include <algorithm>

namespace rtm {

Channels error_map_channels(const ErrorCauses& e) {
  Channels c;
  c.width = e.width;
  c.height = e.height;
  c.names = {"generation", "kind", "cause", "primitive", "reference_primitive"};
  c.values.reserve(e.pixels.size() * c.names.size());
  for (const PixelCause& p : e.pixels) {
    const bool differs = p.cause != ErrorCause::None;
    for (float v : {float(p.generation), differs ? float(p.kind) : -1.0f, float(p.cause),
                    float(p.prim), float(p.reference_prim)})
      c.values.push_back(v);
  }
  return c;
}

Vec3 cause_colour(ErrorCause c) {
  switch (c) {
    case ErrorCause::None:
      break;
    case ErrorCause::Missed:
      return {1, 0, 0};  // red
    case ErrorCause::ExtraHit:
      return {1, 0.5, 0};  // orange
    case ErrorCause::OtherPrimitive:
      return {1, 0, 1};  // magenta
    case ErrorCause::ShadowBlocked:
      return {0, 0.3, 1};  // blue
    case ErrorCause::ShadowUnblocked:
      return {0, 1, 1};  // cyan
    case ErrorCause::HitPoint:
      return {1, 1, 0};  // yellow
    case ErrorCause::Spawned:
      return {0, 1, 0};  // green
    case ErrorCause::Brightness:
      return {1, 1, 1};  // white
    case ErrorCause::Unknown:
      return {0.6, 0.3, 0.1};  // brown
  }
  return {0, 0, 0};
}

Image error_map_picture(const ErrorCauses& e, const Image& machine) {
  Image out(e.width, e.height);
  for (size_t i = 0; i < out.rgb.size(); ++i) {
    const ErrorCause c = e.pixels[i].cause;
    if (c != ErrorCause::None) {
      out.rgb[i] = cause_colour(c);
      continue;
    }
    const Vec3 v = glm::clamp(machine.rgb[i], Vec3(0), Vec3(1));
    out.rgb[i] = Vec3(0.4 * (0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z));
  }
  return out;
}

}  // namespace rtm
