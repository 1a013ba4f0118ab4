// Random inputs and failure tallies the geometry and rendering tests share.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>

#include "geom/vec.h"

namespace rtm::test {

inline double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
/// 10^x for x uniform in [lo_exp, hi_exp]: magnitudes spread evenly over decades.
inline double log_uniform(std::mt19937& rng, double lo_exp, double hi_exp) { return std::pow(10.0, uniform(rng, lo_exp, hi_exp)); }
inline double random_sign(std::mt19937& rng) { return (rng() & 1) ? 1.0 : -1.0; }

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
