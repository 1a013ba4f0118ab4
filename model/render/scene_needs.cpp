#include "render/scene_needs.h"

#include "render/ray.h"

#include <algorithm>
#include <cmath>

namespace rtm {

template <class Real>
SceneNeeds analyse_scene(const Scene& s, const std::vector<CoefRam<Real>>& rams) {
  SceneNeeds n;
  // Only materials some primitive uses matter.
  double ks = 0, kt = 0;
  bool diffuse_used = false;
  for (const Primitive& p : s.primitives) {
    const Material& m = s.materials[size_t(p.material)];
    ks = std::max(ks, m.specular);
    kt = std::max(kt, m.transmission);
    diffuse_used = diffuse_used || m.diffuse > 0;
  }
  n.shadow_rays = diffuse_used && !s.lights.empty();
  n.reflected_rays = s.max_depth > 1 && ks > s.threshold;
  n.transmitted_rays = s.max_depth > 1 && kt > s.threshold;
  n.background = s.background != Vec3(0, 0, 0);
  // A branch ray of generation d has contribution at most max(ks, kt)^(d−1).
  const double k = std::max(ks, kt);
  double c = 1;
  // max_depth is at most kMaxRayDepth in a validated scene; the bound keeps d from overflowing
  // anyway.
  for (int d = 2; d <= std::min(s.max_depth, kMaxRayDepth); ++d) {
    c *= k;
    if (!(c > s.threshold)) break;
    n.deepest_generation = d;
  }
  for (size_t i = 0; i < s.primitives.size(); ++i) {
    n.mac_ops.push_back(sparse_ops(rams[i]));
    n.products_full += kMacProducts;
    n.products_sparse += n.mac_ops.back().size();
    n.clipped.push_back(!s.primitives[i].clips.empty());
    n.clipped_primitives += n.clipped.back();
  }
  Aabb box;
  for (const Primitive& p : s.primitives) box.extend(p.bounds);
  const bool fixed = s.grid.resolution != std::array<int, 3>{0, 0, 0};
  if (fixed)
    n.grid = s.grid.resolution;
  else if (!s.primitives.empty())
    n.grid = scene_resolution(s.primitives, box, s.grid);
  return n;
}

template SceneNeeds analyse_scene<float>(const Scene&, const std::vector<CoefRam<float>>&);
template SceneNeeds analyse_scene<double>(const Scene&, const std::vector<CoefRam<double>>&);

}  // namespace rtm
