// Numerical options of the MAC and the root unit: what the machine can do against float32's
// narrow range and its cancellations (docs/numerics.md has the cases, the measurements and the
// costs). The reference renderer runs with the defaults, the machine with its configuration.
#pragma once

#include <cmath>
#include <algorithm>
#include <cstdint>

#include "geom/intersect.h"

namespace rtm {

/// x rounded to Real, as a double. Through a volatile: GCC 12's SLP vectoriser at -O2 drops the
/// double → float → double round trip when it vectorises several of them (it did in
/// SceneMemory's centres, so float32 coefficients and latches were re-centred on different points).
template <class Real>
double round_to_real(double x) {
  volatile Real r = static_cast<Real>(x);
  return static_cast<double>(r);
}

/// How a primitive's coefficients are scaled before they are written into the coefficient RAM.
enum class CoefScaling : uint8_t {
  None,  ///< the quadric's own coefficients (the paper)
  Pow2,  ///< all ten multiplied by 2^-k so the largest has magnitude in [1, 2)
};

/// The exponent k with 2^-k · max|c| in [1, 2) (0 for a zero quadric). Scaling all ten
/// coefficients by the same power of two scales α, β, γ by it too; the roots do not change, and as
/// long as nothing overflows or goes subnormal no rounding changes either, so the results are
/// bit for bit those of the unscaled coefficients: only coefficients such as 1e±20, whose
/// products leave float32's range, are affected, and for them it is the cure.
inline int pow2_scale_exponent(const Quadric& q) {
  double m = 0;
  for (double c : q.c) m = std::max(m, std::abs(c));
  return m > 0 && std::isfinite(m) ? std::ilogb(m) : 0;
}

/// The same surface with every coefficient multiplied by 2^-pow2_scale_exponent(q): exact in
/// double unless a coefficient is below 2^-1022 of the largest one.
inline Quadric scaled_pow2(const Quadric& q) {
  const int k = pow2_scale_exponent(q);
  Quadric s = q;
  for (double& c : s.c) c = std::ldexp(c, -k);
  return s;
}

/// How the ray origin reaches the MAC's V latches.
enum class OriginLatch : uint8_t {
  Machine,  ///< V rounded to the machine precision, then minus the primitive's centre (the paper's
            ///< latch)
  Wide,     ///< V − centre formed in fp64 (the ray record keeps its origin in fp64), then rounded
  Advance,  ///< as wide, from V + t_enter·U, the point where the ray enters the voxel; the root
            ///< unit adds t_enter back to the roots (rays far from their eye)
};

/// What the shading stage does with the intersection stage's t before it shades the hit.
enum class HitRefine : uint8_t {
  None,    ///< shades at the root unit's t (the paper)
  Newton,  ///< one Newton step on the primitive's local quadric, in fp64, first (render/shade.h)
};

/// The normal the shading stage lights a triangle with, where the triangle has vertex normals
/// (NFF `pp`, a mesh file's): docs/scene-format.md, "Vertex normals".
enum class NormalInterpolation : uint8_t {
  Flat,         ///< the plane's, one normal per primitive (the paper)
  Barycentric,  ///< the vertex normals weighted by the hit's barycentric coordinates
};
/// The default preset's (MachineConfig), and so the reference's on its own (Scene): the files ask
/// for smooth shading; the paper preset sets flat.
inline constexpr NormalInterpolation kDefaultNormalInterpolation = NormalInterpolation::Barycentric;

/// The numerical options of one machine (model/config/config.h has the keys). The reference
/// renderer uses the defaults, so a machine with defaults and fp64 arithmetic reproduces it bit
/// for bit (in fp64 the machine and wide latches give the same bits). docs/numerics.md says why
/// these are the defaults; the paper's machine is plain / none / machine with recentre off.
struct MacNumerics {
  Discriminant discriminant = Discriminant::Plain;
  CoefScaling coef_scaling = CoefScaling::Pow2;
  OriginLatch origin = OriginLatch::Wide;
};

}  // namespace rtm
