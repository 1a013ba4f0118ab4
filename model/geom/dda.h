// 3DDDA (Amanatides & Woo; the paper cites Snyder & Barr): walk a ray through the grid one voxel
// at a time. The whole walk state fits in a ray's payload, so the machine's search units can
// advance a ray one voxel per pass and feed it back.
#pragma once

#include <array>

#include "geom/grid.h"

namespace rtm {

struct DdaState {
  std::array<int, 3> cell{0, 0, 0};
  std::array<double, 3> t_next{kInf, kInf, kInf};  ///< where the ray crosses the next plane on each axis
  double t_enter = 0;                              ///< where the ray enters the current voxel
  double t_exit = 0;                               ///< where it leaves it (>= t_enter)
  bool done = true;                                ///< no current voxel: the ray has left the grid
};

class Dda {
 public:
  /// A walk over o + t d for t in [t_min, t_max]. Zero direction components (either sign) never
  /// step; a ray starting inside, outside or on the boundary starts at its first voxel.
  static DdaState start(const Grid& g, const Vec3& o, const Vec3& d, double t_min, double t_max);

  /// Step to the next voxel; sets done when the index leaves the grid or the voxel starts past t_max.
  /// At most n_x + n_y + n_z steps from any start, so a walk always ends.
  static void advance(const Grid& g, const Vec3& o, const Vec3& d, double t_max, DdaState& s);

  /// True if advance() would end the walk: the last voxel of this ray.
  static bool is_last(const Grid& g, const Vec3& d, double t_max, const DdaState& s);

 private:
  static double crossing(const Grid& g, const Vec3& o, const Vec3& d, int axis, int cell);
  static int exit_axis(const DdaState& s);
};

inline double Dda::crossing(const Grid& g, const Vec3& o, const Vec3& d, int axis, int cell) {
  if (d[axis] == 0) return kInf;  // true for -0.0 too
  const int boundary = d[axis] > 0 ? cell + 1 : cell;
  return (g.plane(axis, boundary) - o[axis]) / d[axis];
}

inline int Dda::exit_axis(const DdaState& s) {
  // Ties (edges and corners) step the lowest axis first; the others follow with zero-length voxels.
  int a = 0;
  if (s.t_next[1] < s.t_next[a]) a = 1;
  if (s.t_next[2] < s.t_next[a]) a = 2;
  return a;
}

inline DdaState Dda::start(const Grid& g, const Vec3& o, const Vec3& d, double t_min, double t_max) {
  DdaState s;
  // A non-finite origin or direction has no walk (std::max / std::min below would silently drop
  // a NaN, and an infinite origin makes o + t d NaN).
  if (!all_finite(o) || !all_finite(d)) return s;
  double t0 = t_min, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (o[a] < g.box.lo[a] || o[a] > g.box.hi[a]) return s;
      continue;
    }
    double ta = (g.box.lo[a] - o[a]) / d[a], tb = (g.box.hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 <= t1)) return s;  // misses the grid, or NaN input
  for (int a = 0; a < 3; ++a) {
    const double p = d[a] == 0 ? o[a] : o[a] + t0 * d[a];
    s.cell[a] = std::clamp(static_cast<int>(std::floor((p - g.box.lo[a]) / g.cell[a])), 0, g.n[a] - 1);
  }
  for (int a = 0; a < 3; ++a) s.t_next[a] = crossing(g, o, d, a, s.cell[a]);
  s.t_enter = t0;
  s.t_exit = std::max(t0, s.t_next[exit_axis(s)]);
  s.done = false;
  return s;
}

inline void Dda::advance(const Grid& g, const Vec3& o, const Vec3& d, double t_max, DdaState& s) {
  const int a = exit_axis(s);
  if (s.t_next[a] == kInf) {
    s.done = true;
    return;
  }
  s.cell[a] += d[a] > 0 ? 1 : -1;
  s.t_enter = s.t_exit;
  if (s.cell[a] < 0 || s.cell[a] >= g.n[a] || s.t_enter > t_max) {
    s.done = true;
    return;
  }
  s.t_next[a] = crossing(g, o, d, a, s.cell[a]);
  s.t_exit = std::max(s.t_enter, s.t_next[exit_axis(s)]);
}

inline bool Dda::is_last(const Grid& g, const Vec3& d, double t_max, const DdaState& s) {
  const int a = exit_axis(s);
  if (s.t_next[a] == kInf || s.t_exit > t_max) return true;
  const int next = s.cell[a] + (d[a] > 0 ? 1 : -1);
  return next < 0 || next >= g.n[a];
}

}  // namespace rtm
