// The checks validate() runs, one per part of a scene, for the parsers to run as they read each
// part (so a message can name the file and line). Each throws std::invalid_argument.
#pragma once

#include <limits>
#include <string>

#include "scene/scene.h"

namespace rtm::scene_checks {

/// The numbers a scene setting may take, declared once: the checks, the parsers' messages and
/// rtm's --help all read it.
struct NumberRange {
  double lo;
  double hi;     ///< infinity: no upper bound
  bool hi_open;  ///< hi itself is outside
  bool contains(double x) const {
    return x >= lo && (hi_open ? x < hi : x <= hi);
  }  // false for NaN
  /// "[0, 1)"; "[0, inf)" without an upper bound.
  std::string text() const;
};

inline constexpr NumberRange kThresholdRange{0, 1, true};
inline constexpr NumberRange kSpawnOffsetRange{0, std::numeric_limits<double>::infinity(), true};

void check_camera(const Camera& c);
void check_resolution(int width, int height);
void check_colour(const Vec3& c, const std::string& what);
void check_light(const Light& l);
void check_material(const Material& m);
void check_max_depth(int max_depth);
void check_grid(const GridOptions& g);

}  // namespace rtm::scene_checks
