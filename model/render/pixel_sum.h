// Order-independent brightness accumulation.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "geom/vec.h"

namespace rtm {

/// A pixel's brightness as a fixed-point sum (quantum 2⁻⁴⁰ ≈ 9e-13): integer addition is
/// associative, so the machine, whose PEs and stages add contributions in whatever order rays
/// finish, produces exactly the same pixel as the depth-first reference renderer.
struct PixelSum {
  static constexpr double kScale = 1099511627776.0;  // 2^40
  std::array<int64_t, 3> q{0, 0, 0};

  void add(const Vec3& v) {
    for (int c = 0; c < 3; ++c)
      q[size_t(c)] += std::llround(std::clamp(v[c], -4.0e6, 4.0e6) * kScale);
  }
  void add(const PixelSum& o) {
    for (size_t c = 0; c < 3; ++c) q[c] += o.q[c];
  }
  Vec3 value() const { return Vec3(double(q[0]), double(q[1]), double(q[2])) / kScale; }
};

}  // namespace rtm
