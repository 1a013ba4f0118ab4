// What a scene can use of the machine, derived from the scene alone: which ray kinds can ever be
// spawned, which MAC products are non-zero, which primitives need clip tests, how deep rays go.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geom/mac_schedule.h"
#include "scene/scene.h"

namespace rtm {

struct SceneNeeds {
  bool shadow_rays = false;       ///< some light, and some material with kd > 0
  bool reflected_rays = false;    ///< max_depth > 1 and some ks above the threshold
  bool transmitted_rays = false;  ///< max_depth > 1 and some kt above the threshold
  bool background = false;        ///< misses add a non-zero background
  /// The deepest ray generation a branch ray can reach: the largest d <= max_depth with
  /// max(ks, kt)^(d−1) > threshold (primary rays are generation 1).
  int deepest_generation = 1;
  std::vector<MacOps> mac_ops;   ///< per primitive: the products with a non-zero coefficient word
  uint64_t products_full = 0;    ///< 28 per primitive
  uint64_t products_sparse = 0;  ///< Σ non-zero products over primitives
  std::vector<bool> clipped;     ///< per primitive: has clip half-spaces
  int clipped_primitives = 0;
  std::array<int, 3> grid{1, 1,
                          1};  ///< the scene's grid resolution: its own, else the automatic one

  bool spawns_rays() const { return shadow_rays || reflected_rays || transmitted_rays; }
};

/// The analysis for the coefficient RAM images the machine would hold (re-centred or not, in
/// the given word precision: a float RAM rounds tiny coefficients to zero exactly as stored).
template <class Real>
SceneNeeds analyse_scene(const Scene& s, const std::vector<CoefRam<Real>>& rams);

}  // namespace rtm
