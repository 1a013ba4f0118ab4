// 3DDDA (Amanatides & Woo; the paper cites Snyder & Barr): walk a ray through the grid one voxel
// at a time. The whole walk state fits in a ray's payload, so the machine's search units can
// advance a ray one voxel per pass and feed it back.
//
// Templated on the search unit's arithmetic (`dda_precision`, docs/numerics.md): every crossing,
// plane position and comparison is in Real, from the ray and the grid rounded to Real; the state
// holds the results as doubles, which hold a float exactly. Dda is the double-precision walk the
// reference renderer takes.
#pragma once

#include <array>
#include <limits>

#include "geom/grid.h"

namespace rtm {

struct DdaState {
  std::array<int, 3> cell{0, 0, 0};
  std::array<double, 3> t_next{kInf, kInf,
                               kInf};  ///< where the ray crosses the next plane on each axis
  double t_enter = 0;                  ///< where the ray enters the current voxel
  double t_exit = 0;                   ///< where it leaves it (>= t_enter)
  /// How far past the true entry the rounded t_enter may lie: the bound of its crossing's rounding
  /// in the walk's arithmetic (0 at the ray's own start). A voxel test reaches back this far, so a
  /// hit just past the entry face is found in this voxel whatever the rounding.
  double t_enter_slack = 0;
  bool done = true;  ///< no current voxel: the ray has left the grid
};

template <class Real>
class BasicDda {
 public:
  using V = glm::vec<3, Real>;

  /// A walk over o + t d for t in [t_min, t_max]. Zero direction components (either sign) never
  /// step; a ray starting inside, outside or on the boundary starts at its first voxel.
  static DdaState start(const Grid& g, const Vec3& o, const Vec3& d, double t_min, double t_max);

  /// Step to the next voxel; sets done when the index leaves the grid or the voxel starts past
  /// t_max. At most n_x + n_y + n_z steps from any start, so a walk always ends.
  static void advance(const Grid& g, const Vec3& o, const Vec3& d, double t_max, DdaState& s);

  /// The crossing after t_next on each axis (kInf on an axis the ray does not step along), for
  /// advance_ahead(); refill after start() and skip_box().
  static std::array<double, 3> ahead(const Grid& g, const Vec3& o, const Vec3& d,
                                     const DdaState& s);
  /// advance() with each axis's next crossing computed one step ahead: the same states, but no
  /// division stands between one step's choice of axis and the next one's (the reference
  /// renderer's walk, where that latency was the largest single cost).
  static void advance_ahead(const Grid& g, const Vec3& o, const Vec3& d, double t_max, DdaState& s,
                            std::array<double, 3>& ahead);

  /// True if advance() would end the walk: the last voxel of this ray.
  static bool is_last(const Grid& g, const Vec3& d, double t_max, const DdaState& s);

  /// Moves the walk from its voxel to the last voxel it visits inside the box of cells [lo, hi]
  /// (which holds its voxel), leaving `s` exactly as the advance() calls it replaces would;
  /// returns how many calls that is (0: `s` unchanged, also when the walk ends in the box).
  /// For crossing voxels known to be empty at once, in a few divisions instead of one per voxel.
  static int skip_box(const Grid& g, const Vec3& o, const Vec3& d, double t_max, DdaState& s,
                      const std::array<int, 3>& lo, const std::array<int, 3>& hi);

 private:
  static constexpr Real kInfR = std::numeric_limits<Real>::infinity();
  /// A voxel plane from its index, in Real (no accumulated drift).
  static Real plane(const Grid& g, int axis, int i) {
    return Real(g.box.lo[axis]) + Real(i) * Real(g.cell[axis]);
  }
  static Real crossing(const Grid& g, const V& o, const V& d, int axis, int cell);
  /// The rounding bound of a crossing at t on `axis`: t = (P − o)/d with P, o and d rounded to
  /// Real, and |P| <= |o| + |t d|, is within 8 ε (|o| / |d| + |t|) of the exact crossing.
  static double slack(const Vec3& o, const Vec3& d, int axis, double t) {
    return 8 * double(std::numeric_limits<Real>::epsilon()) *
           (std::abs(o[axis] / d[axis]) + std::abs(t));
  }
  static int exit_axis(const DdaState& s);
};

using Dda = BasicDda<double>;

template <class Real>
Real BasicDda<Real>::crossing(const Grid& g, const V& o, const V& d, int axis, int cell) {
  if (d[axis] == 0) return kInfR;  // true for -0.0 too
  const int boundary = d[axis] > 0 ? cell + 1 : cell;
  return (plane(g, axis, boundary) - o[axis]) / d[axis];
}

template <class Real>
int BasicDda<Real>::exit_axis(const DdaState& s) {
  // Ties (edges and corners) step the lowest axis first; the others follow with zero-length voxels.
  int a = 0;
  if (s.t_next[1] < s.t_next[a]) a = 1;
  if (s.t_next[2] < s.t_next[a]) a = 2;
  return a;
}

template <class Real>
DdaState BasicDda<Real>::start(const Grid& g, const Vec3& o_in, const Vec3& d_in, double t_min,
                               double t_max) {
  DdaState s;
  // A non-finite origin or direction has no walk (std::max / std::min below would silently drop
  // a NaN, and an infinite origin makes o + t d NaN); so has one beyond Real's range.
  const V o(o_in), d(d_in);
  auto finite = [](const V& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  if (!finite(o) || !finite(d)) return s;
  Real t0 = Real(t_min), t1 = Real(t_max);
  int entry_axis = -1;  // the face the walk enters the grid by; -1: it starts at t_min
  for (int a = 0; a < 3; ++a) {
    const Real lo = Real(g.box.lo[a]), hi = Real(g.box.hi[a]);
    if (d[a] == 0) {
      if (o[a] < lo || o[a] > hi) return s;
      continue;
    }
    Real ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    if (ta > t0) entry_axis = a;
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 <= t1)) return s;  // misses the grid, or NaN input
  for (int a = 0; a < 3; ++a) {
    const Real p = d[a] == 0 ? o[a] : o[a] + t0 * d[a];
    s.cell[a] = std::clamp(static_cast<int>(std::floor((p - Real(g.box.lo[a])) / Real(g.cell[a]))),
                           0, g.n[a] - 1);
  }
  for (int a = 0; a < 3; ++a) s.t_next[a] = crossing(g, o, d, a, s.cell[a]);
  s.t_enter = t0;
  s.t_enter_slack =
      entry_axis < 0 ? 0.0 : std::min(double(t0) - t_min, slack(o_in, d_in, entry_axis, t0));
  s.t_exit = std::max(double(t0), s.t_next[exit_axis(s)]);
  s.done = false;
  return s;
}

template <class Real>
void BasicDda<Real>::advance(const Grid& g, const Vec3& o, const Vec3& d, double t_max,
                             DdaState& s) {
  const int a = exit_axis(s);
  if (s.t_next[a] == kInf) {
    s.done = true;
    return;
  }
  s.cell[a] += d[a] > 0 ? 1 : -1;
  s.t_enter = s.t_exit;
  s.t_enter_slack = slack(o, d, a, s.t_enter);
  if (s.cell[a] < 0 || s.cell[a] >= g.n[a] || s.t_enter > double(Real(t_max))) {
    s.done = true;
    return;
  }
  s.t_next[a] = crossing(g, V(o), V(d), a, s.cell[a]);
  s.t_exit = std::max(s.t_enter, s.t_next[exit_axis(s)]);
}

template <class Real>
std::array<double, 3> BasicDda<Real>::ahead(const Grid& g, const Vec3& o, const Vec3& d,
                                            const DdaState& s) {
  std::array<double, 3> t{kInf, kInf, kInf};
  for (int a = 0; a < 3; ++a)
    if (d[a] != 0) t[a] = crossing(g, V(o), V(d), a, s.cell[a] + (d[a] > 0 ? 1 : -1));
  return t;
}

template <class Real>
void BasicDda<Real>::advance_ahead(const Grid& g, const Vec3& o, const Vec3& d, double t_max,
                                   DdaState& s, std::array<double, 3>& ahead) {
  const int a = exit_axis(s);
  if (s.t_next[a] == kInf) {
    s.done = true;
    return;
  }
  const int dir = d[a] > 0 ? 1 : -1;
  s.cell[a] += dir;
  s.t_enter = s.t_exit;
  s.t_enter_slack = slack(o, d, a, s.t_enter);
  if (s.cell[a] < 0 || s.cell[a] >= g.n[a] || s.t_enter > double(Real(t_max))) {
    s.done = true;
    return;
  }
  s.t_next[a] = ahead[a];
  ahead[a] = crossing(g, V(o), V(d), a, s.cell[a] + dir);
  s.t_exit = std::max(s.t_enter, s.t_next[exit_axis(s)]);
}

template <class Real>
bool BasicDda<Real>::is_last(const Grid& g, const Vec3& d, double t_max, const DdaState& s) {
  const int a = exit_axis(s);
  if (s.t_next[a] == kInf || s.t_exit > double(Real(t_max))) return true;
  const int next = s.cell[a] + (d[a] > 0 ? 1 : -1);
  return next < 0 || next >= g.n[a];
}

// advance() crosses planes in order of (t, axis), ties to the lower axis, and each axis's
// crossings grow monotonically with its cell index (t_next is recomputed from the index, so
// there is no drift): the walk is a merge of three sorted lists. It leaves the box at the first
// of the three "leave the box's last cell on this axis" crossings; every crossing ordered before
// that one happens inside the box, and counting them per axis gives the cell where the walk
// stands just before it leaves.
template <class Real>
int BasicDda<Real>::skip_box(const Grid& g, const Vec3& o_in, const Vec3& d_in, double t_max,
                             DdaState& s, const std::array<int, 3>& lo,
                             const std::array<int, 3>& hi) {
  const V o(o_in), d(d_in);
  std::array<int, 3> last = s.cell;  // the box's last cell on each axis, in the walk's direction
  std::array<double, 3> t_last{kInf, kInf, kInf};
  double t_out = kInf;
  int axis_out = -1;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) continue;
    last[a] = d[a] > 0 ? hi[a] : lo[a];
    t_last[a] = crossing(g, o, d, a, last[a]);
    if (t_last[a] < t_out) {  // strict: a tie goes to the lower axis
      t_out = t_last[a];
      axis_out = a;
    }
  }
  if (axis_out < 0 || !(t_out <= double(Real(t_max)))) return 0;

  DdaState n = s;
  int steps = 0;
  int entry_axis = -1;  // the axis whose crossing n.t_enter is
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) continue;
    const int dir = d[a] > 0 ? 1 : -1;
    const int room = (last[a] - s.cell[a]) * dir;  // crossings of this axis inside the box
    // The k-th crossing of this axis: leaving cell + k·dir.
    auto cross = [&](int k) {
      return k == room ? t_last[a] : double(crossing(g, o, d, a, s.cell[a] + k * dir));
    };
    int k = room;  // on the way-out axis, every crossing before the last cell's is made
    double t_k = t_last[a], t_before = kInf;  // crossings k and k - 1
    if (a != axis_out) {
      // Crossings ordered before the way out are made. Start from where the ray is at t_out and
      // settle on the exact count by the crossings themselves (usually two divisions, whatever
      // the box's size). The box's last crossing on this axis is never before the way out.
      auto before = [&](double t) { return t < t_out || (t == t_out && a < axis_out); };
      const double first = plane(g, a, d[a] > 0 ? s.cell[a] + 1 : s.cell[a]);
      const double est = ((o[a] + t_out * d[a]) - first) * dir / g.cell[a] + 1;
      k = !(est > 0) ? 0 : est >= room ? room : static_cast<int>(est);
      t_k = cross(k);
      if (before(t_k)) {
        do {
          t_before = t_k;
          t_k = cross(++k);
        } while (before(t_k));
      } else {
        for (; k > 0; --k) {
          t_before = cross(k - 1);
          if (before(t_before)) break;
          t_k = t_before;
        }
      }
    } else if (k > 0) {
      t_before = cross(k - 1);
    }
    if (k == 0) continue;
    n.cell[a] = s.cell[a] + k * dir;
    n.t_next[a] = t_k;
    if (t_before >= n.t_enter) entry_axis = a;  // ties: advance() crosses the lowest axis first
    n.t_enter = std::max(n.t_enter, t_before);  // t_enter is the running maximum of t_exit
    steps += k;
  }
  if (steps == 0) return 0;
  if (entry_axis >= 0) n.t_enter_slack = slack(o_in, d_in, entry_axis, n.t_enter);
  n.t_exit = std::max(n.t_enter, n.t_next[exit_axis(n)]);
  s = n;
  return steps;
}

}  // namespace rtm
