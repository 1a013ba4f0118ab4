// Random inputs and failure tallies the geometry and rendering tests share.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>

#include "geom/vec.h"

namespace rtm::test {

inline double uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
/// 10^x for x uniform in [lo_exp, hi_exp]: magnitudes spread evenly over decades.
inline double log_uniform(std::mt19937& rng, double lo_exp, double hi_exp) {
  return std::pow(10.0, uniform(rng, lo_exp, hi_exp));
}
inline double random_sign(std::mt19937& rng) { return (rng() & 1) ? 1.0 : -1.0; }

// Draws in the arguments of one call or the operands of one operator come in an order the
// language leaves to the compiler (GCC takes a call's arguments, glm's operators' included, right
// to left; clang left to right), so the tests draw one a statement, in GCC's order: their figures
// (and docs/numerics.md's) were measured with it.

/// ±10^x, x uniform in [lo_exp, hi_exp]; the sign drawn first.
inline double signed_log_uniform(std::mt19937& rng, double lo_exp, double hi_exp) {
  const double sign = random_sign(rng);
  return sign * log_uniform(rng, lo_exp, hi_exp);
}

/// A point uniform in [lo, hi)^3, its z drawn first, then y, then x.
inline Vec3 uniform_zyx(std::mt19937& rng, double lo, double hi) {
  const double z = uniform(rng, lo, hi), y = uniform(rng, lo, hi);
  return Vec3{uniform(rng, lo, hi), y, z};
}

/// A direction uniform on the sphere.
inline Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> n;
  for (;;) {
    const Vec3 v{n(rng), n(rng), n(rng)};
    if (length(v) > 1e-3) return normalize(v);
  }
}

/// A batch of cases: how many, how many wrong, the worst error; printed so the figures in
/// docs/numerics.md can be re-measured.
struct Tally {
  int n = 0, wrong = 0;
  double worst = 0;
  void add(bool ok, double err = 0) {
    ++n;
    wrong += !ok;
    if (std::isfinite(err)) worst = std::max(worst, err);
  }
  double rate() const { return n ? double(wrong) / n : 0; }
};

}  // namespace rtm::test
