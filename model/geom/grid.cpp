#include "geom/grid.h"

#include <climits>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace rtm {
namespace {

struct Interval {
  double lo, hi;
};

Interval operator+(Interval a, Interval b) { return {a.lo + b.lo, a.hi + b.hi}; }

Interval scale(double k, Interval a) {
  return k >= 0 ? Interval{k * a.lo, k * a.hi} : Interval{k * a.hi, k * a.lo};
}

Interval mul(Interval a, Interval b) {
  const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  return {std::min({p[0], p[1], p[2], p[3]}), std::max({p[0], p[1], p[2], p[3]})};
}

/// x² is never negative: tighter than mul(a, a) when the interval straddles zero.
Interval square(Interval a) {
  const double l = a.lo * a.lo, h = a.hi * a.hi;
  if (a.lo <= 0 && a.hi >= 0) return {0, std::max(l, h)};
  return {std::min(l, h), std::max(l, h)};
}

/// Voxels are grown by this fraction of their size when registering primitives, so surfaces on
/// a voxel face, and hits computed in float32 a little off the true surface, still find their
/// primitive listed.
constexpr double kVoxelPad = 1e-3;

/// Voxel (x, y, z)'s box grown by kVoxelPad of a cell on every side, as the overlap tests see it.
Aabb padded_voxel_box(const Grid& g, int x, int y, int z) {
  Aabb b = g.voxel_box(x, y, z);
  b.lo -= kVoxelPad * g.cell;
  b.hi += kVoxelPad * g.cell;
  return b;
}

}  // namespace

Aabb Grid::voxel_box(int x, int y, int z) const {
  return Aabb{{plane(0, x), plane(1, y), plane(2, z)},
              {plane(0, x + 1), plane(1, y + 1), plane(2, z + 1)}};
}

namespace {

/// Naive interval form in world coordinates: each term bounded on its own. Tight near the origin,
/// but far from it the terms (x² and −2cx·x for a sphere) cancel and the bound grows useless.
bool may_vanish_world(const Quadric& q, const Aabb& b) {
  const Interval x{b.lo.x, b.hi.x}, y{b.lo.y, b.hi.y}, z{b.lo.z, b.hi.z};
  const auto& c = q.c;
  Interval v = scale(c[kA], square(x)) + scale(c[kB], square(y)) + scale(c[kC], square(z)) +
               scale(c[kD], mul(x, y)) + scale(c[kE], mul(y, z)) + scale(c[kF], mul(z, x)) +
               scale(c[kG], x) + scale(c[kH], y) + scale(c[kI], z) + Interval{c[kJ], c[kJ]};
  // Rounding in the sums above is far below this slack, which is relative to the terms' size.
  double mag = 0;
  for (double t : {std::abs(v.lo), std::abs(v.hi), std::abs(c[kJ])}) mag = std::max(mag, t);
  const double slack = 1e-12 * mag;
  return v.lo <= slack && v.hi >= -slack;
}

/// Exact range of a u² + g u over |u| <= h.
Interval axis_range(double a, double g, double h) {
  const double f0 = (a * h - g) * h, f1 = (a * h + g) * h;  // at u = −h, u = +h
  Interval r{std::min(f0, f1), std::max(f0, f1)};
  if (a != 0) {
    const double u = -g / (2 * a);
    if (std::abs(u) < h) {
      const double fv = -g * g / (4 * a);
      r.lo = std::min(r.lo, fv);
      r.hi = std::max(r.hi, fv);
    }
  }
  return r;
}

/// Centred form about the box centre m: Q(m + u) = Q(m) + Σ (A_ii u_i² + ∂_iQ(m) u_i) + cross
/// terms, exact for a quadric. The per-axis parts are bounded exactly and the cross terms by
/// ±|D| h_x h_y etc., so the bound is as tight far from the origin as near it (exact for spheres).
bool may_vanish_centred(const Quadric& q, const Aabb& b) {
  const auto& c = q.c;
  const Vec3 m = (b.lo + b.hi) * 0.5;
  const Vec3 h = glm::max(b.hi - m, m - b.lo);
  const Vec3 g = q.gradient(m);
  const double q0 = q.value(m);
  const double cross_bound =
      std::abs(c[kD]) * h.x * h.y + std::abs(c[kE]) * h.y * h.z + std::abs(c[kF]) * h.z * h.x;
  Interval v{q0 - cross_bound, q0 + cross_bound};
  v = v + axis_range(c[kA], g.x, h.x) + axis_range(c[kB], g.y, h.y) + axis_range(c[kC], g.z, h.z);
  // Rounding: relative to the magnitude of every term summed into Q(m), ∇Q(m) and the bounds.
  const Vec3 am = glm::abs(m);
  const double q_terms = std::abs(c[kA]) * am.x * am.x + std::abs(c[kB]) * am.y * am.y +
                         std::abs(c[kC]) * am.z * am.z + std::abs(c[kD]) * am.x * am.y +
                         std::abs(c[kE]) * am.y * am.z + std::abs(c[kF]) * am.z * am.x +
                         std::abs(c[kG]) * am.x + std::abs(c[kH]) * am.y + std::abs(c[kI]) * am.z +
                         std::abs(c[kJ]);
  const Vec3 g_terms{2 * std::abs(c[kA]) * am.x + std::abs(c[kD]) * am.y + std::abs(c[kF]) * am.z +
                         std::abs(c[kG]),
                     2 * std::abs(c[kB]) * am.y + std::abs(c[kD]) * am.x + std::abs(c[kE]) * am.z +
                         std::abs(c[kH]),
                     2 * std::abs(c[kC]) * am.z + std::abs(c[kE]) * am.y + std::abs(c[kF]) * am.x +
                         std::abs(c[kI])};
  const double quad_terms =
      std::abs(c[kA]) * h.x * h.x + std::abs(c[kB]) * h.y * h.y + std::abs(c[kC]) * h.z * h.z;
  const double mag = q_terms + dot(g_terms, h + am) + quad_terms + cross_bound;
  const double slack = 1e-12 * mag;
  return v.lo <= slack && v.hi >= -slack;
}

}  // namespace

bool quadric_may_vanish(const Quadric& q, const Aabb& b) {
  // Both forms enclose Q's range over the box; a zero must lie in each.
  return may_vanish_centred(q, b) && may_vanish_world(q, b);
}

bool box_touches_halfspace(const Aabb& b, const HalfSpace& h) {
  // The box corner minimising n·p.
  const Vec3 p{h.n.x >= 0 ? b.lo.x : b.hi.x, h.n.y >= 0 ? b.lo.y : b.hi.y,
               h.n.z >= 0 ? b.lo.z : b.hi.z};
  return h.eval(p) <= 1e-12 * (max_abs(h.n) * max_abs(p) + std::abs(h.d));
}

std::array<int, 3> auto_resolution(const Aabb& box, size_t primitives, const GridOptions& opt) {
  if (!(std::isfinite(opt.voxels_per_primitive) && opt.voxels_per_primitive > 0))
    throw std::invalid_argument("voxels_per_primitive must be a finite positive number");
  const Vec3 e = box.extent();
  const double target = opt.voxels_per_primitive * double(std::max<size_t>(primitives, 1));
  const int max_axis = std::max(1, opt.max_auto_axis);
  // Cubic voxels of edge 1/per_unit, per_unit = (target / volume)^(1/k) over the k axes that get
  // more than one voxel. An axis thinner than one such voxel (a flat or nearly flat scene) gets
  // exactly one, and the budget is spent on the others: recompute until no more axes drop out.
  bool active[3];
  for (int a = 0; a < 3; ++a) active[a] = std::isfinite(e[a]) && e[a] > 0;
  double per_unit = 0;
  for (;;) {
    double volume = 1;
    int k = 0;
    for (int a = 0; a < 3; ++a)
      if (active[a]) volume *= e[a], ++k;
    if (k == 0) break;
    per_unit = std::pow(target / volume, 1.0 / k);
    bool dropped = false;
    for (int a = 0; a < 3; ++a)
      if (active[a] && e[a] * per_unit < 1) active[a] = false, dropped = true;
    if (!dropped) break;
  }
  std::array<int, 3> n{1, 1, 1};
  for (int a = 0; a < 3; ++a)
    if (active[a])
      n[a] = std::clamp(int(std::lround(std::min(e[a] * per_unit, double(max_axis)))), 1, max_axis);
  return n;
}

bool sphere_touches_box(const Vec3& c, double r, const Aabb& b) {
  double n2[3], f2[3];
  for (int a = 0; a < 3; ++a) {
    const double lo = b.lo[a] - c[a], hi = b.hi[a] - c[a];
    const double n = lo > 0 ? lo : (hi < 0 ? -hi : 0);
    n2[a] = n * n;
    f2[a] = std::max(lo * lo, hi * hi);
  }
  // Summed z, y, x: the order build_grid's row-by-row form uses, so both round alike.
  const double near2 = n2[2] + n2[1] + n2[0], far2 = f2[2] + f2[1] + f2[0];
  // Rounding in the differences is relative to the coordinates, not to the radius.
  const double scale = max_abs(c) + r + max_abs(b.extent());
  const double slack = 1e-12 * scale * scale;
  return near2 <= r * r + slack && far2 >= r * r - slack;
}

double estimated_references(const std::vector<Primitive>& prims, const Aabb& box,
                            const std::array<int, 3>& n) {
  const Vec3 cell = box.extent() / Vec3(n[0], n[1], n[2]);
  const double edge = std::max({cell.x, cell.y, cell.z});
  double total = 0;
  for (const Primitive& p : prims) {
    double voxels = 1;
    for (int a = 0; a < 3; ++a) {
      const double span = cell[a] > 0 ? p.bounds.extent()[a] / cell[a] : 0;
      voxels *=
          std::min(double(n[a]), span + 1);  // the cells a box of that width spans, on average
    }
    if (p.kind == ShapeKind::Sphere && p.r0 > 0) voxels *= std::min(1.0, 2.4 * edge / p.r0);
    total += voxels;
  }
  return total;
}

namespace {

/// The resolution n coarsened, every axis by the same factor, until estimated_references is
/// within the budget or within twice the voxels (or every axis is down to one voxel). The build
/// costs the voxels (the start array) plus the references, so references below the order of the
/// voxels are not worth a coarser grid: a floor under a few objects (SPD tree-3) keeps its grid.
std::array<int, 3> within_reference_budget(const std::vector<Primitive>& prims, const Aabb& box,
                                           std::array<int, 3> n, double budget) {
  auto scaled = [&](double s) {
    std::array<int, 3> m{};
    for (int a = 0; a < 3; ++a) m[a] = std::max(1, int(std::lround(n[a] * s)));
    return m;
  };
  auto within = [&](const std::array<int, 3>& m) {
    return estimated_references(prims, box, m) <=
           std::max(budget, 2.0 * double(m[0]) * m[1] * m[2]);
  };
  if (within(n)) return n;
  double lo = 0, hi = 1;  // scaled(hi) is over the budget
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (lo + hi);
    (within(scaled(mid)) ? lo : hi) = mid;
  }
  return scaled(lo);
}

}  // namespace

std::array<int, 3> scene_resolution(const std::vector<Primitive>& prims, const Aabb& box,
                                    const GridOptions& opt) {
  std::array<int, 3> n = density_resolution(prims, box, opt);
  if (opt.max_refs_per_primitive > 0)
    n = within_reference_budget(
        prims, box, n, opt.max_refs_per_primitive * double(std::max<size_t>(1, prims.size())));
  return n;
}

std::array<int, 3> density_resolution(const std::vector<Primitive>& prims, const Aabb& box,
                                      const GridOptions& opt) {
  if (prims.size() < 8) return auto_resolution(box, prims.size(), opt);
  // The dense core: central 90% of centres per axis, grown by half the median primitive size.
  std::vector<double> c[3], size;
  for (const Primitive& p : prims) {
    const Vec3 m = 0.5 * (p.bounds.lo + p.bounds.hi), e = p.bounds.extent();
    for (int a = 0; a < 3; ++a) c[a].push_back(m[a]);
    size.push_back(std::max({e.x, e.y, e.z}));
  }
  auto quantile = [](std::vector<double>& v, double q) {
    auto it = v.begin() + std::ptrdiff_t(q * double(v.size() - 1));
    std::nth_element(v.begin(), it, v.end());
    return *it;
  };
  const double grow = 0.5 * quantile(size, 0.5);
  Aabb core;
  for (int a = 0; a < 3; ++a) {
    core.lo[a] = std::max(box.lo[a], quantile(c[a], 0.05) - grow);
    core.hi[a] = std::min(box.hi[a], quantile(c[a], 0.95) + grow);
  }
  size_t inside = 0;
  for (const Primitive& p : prims) {
    const Vec3 m = 0.5 * (p.bounds.lo + p.bounds.hi);
    inside += m.x >= core.lo.x && m.x <= core.hi.x && m.y >= core.lo.y && m.y <= core.hi.y &&
              m.z >= core.lo.z && m.z <= core.hi.z;
  }
  // Voxel edge from the core (uncapped), then the whole box at that edge, capped.
  GridOptions uncapped = opt;
  uncapped.max_auto_axis = INT32_MAX / 4;
  const std::array<int, 3> nc = auto_resolution(core, std::max<size_t>(inside, 1), uncapped);
  double per_unit = 0;
  for (int a = 0; a < 3; ++a)
    if (core.extent()[a] > 0 && nc[a] > 1) per_unit = std::max(per_unit, nc[a] / core.extent()[a]);
  if (!(per_unit > 0)) return auto_resolution(box, prims.size(), opt);
  const std::array<int, 3> whole = auto_resolution(box, prims.size(), opt);
  // The core's edge on every axis, capped at `cap` voxels an axis, and (with an aspect limit) no
  // edge shorter than 1/max_auto_aspect of the longest.
  const Vec3 e = box.extent();
  const double core_edge = 1 / per_unit, longest_extent = std::max({e.x, e.y, e.z});
  auto laid = [&](double cap) {
    const double shortest = opt.max_auto_aspect > 0
                                ? std::max(core_edge, longest_extent / cap) / opt.max_auto_aspect
                                : 0;
    const double voxels_per_unit = std::min(per_unit, 1 / shortest);  // per_unit without a limit
    std::array<int, 3> n{};
    for (int a = 0; a < 3; ++a)
      n[a] = std::clamp(int(std::lround(std::min(e[a] * voxels_per_unit, cap))), 1,
                        std::max(1, opt.max_auto_axis));
    return n;
  };
  auto cells = [](const std::array<int, 3>& n) { return double(n[0]) * n[1] * n[2]; };
  double cap = std::max(1, opt.max_auto_axis);
  if (opt.max_auto_cells > 0 && cells(laid(cap)) > double(opt.max_auto_cells)) {
    // The largest cap within the budget, by bisection (the count falls as the cap does).
    double lo = 1;
    for (int i = 0; i < 60; ++i) {
      const double mid = std::sqrt(lo * cap);
      (cells(laid(mid)) > double(opt.max_auto_cells) ? cap : lo) = mid;
    }
    cap = lo;
  }
  std::array<int, 3> n = laid(cap);
  // Never coarser than the plain rule over the whole box.
  for (int a = 0; a < 3; ++a) n[a] = std::max(n[a], whole[a]);
  return n;
}

Grid build_grid(const std::vector<Primitive>& prims, const GridOptions& opt, int threads,
                const StepProgress& progress) {
  auto tell = [&](const char* step, const char* item, uint64_t done, uint64_t total) {
    if (progress) progress(step, item, done, total);
  };
  tell("grid build", "", 0, 0);  // choosing the resolution
  Grid g;
  for (const Primitive& p : prims) g.box.extend(p.bounds);
  if (prims.empty()) g.box = Aabb{{0, 0, 0}, {1, 1, 1}};
  // Pad the object space so surfaces lying on its boundary are strictly inside.
  const Vec3 e = g.box.extent();
  const double pad = 1e-6 * std::max({e.x, e.y, e.z, 1e-300});
  g.box.lo -= Vec3(pad);
  g.box.hi += Vec3(pad);

  const bool automatic = opt.resolution == std::array<int, 3>{0, 0, 0};
  g.n = automatic ? scene_resolution(prims, g.box, opt) : opt.resolution;
  for (int a = 0; a < 3; ++a)
    if (g.n[a] < 1)
      throw std::invalid_argument("grid resolution must be at least 1 voxel per axis");
  if (double(g.n[0]) * g.n[1] * g.n[2] > 1.5e9)
    throw std::invalid_argument("grid resolution is too large");
  g.cell = g.box.extent() / Vec3(g.n[0], g.n[1], g.n[2]);

  // (voxel, primitive) pairs in primitive order, each thread a contiguous run of primitives, then
  // a counting sort by voxel into one contiguous array (the PE's voxel data); each voxel's list
  // stays in primitive order, whatever the number of threads.
  using Ref = std::pair<uint32_t, uint32_t>;  // voxel (< 1.5e9), primitive
  // The exact sphere test, voxel by voxel as sphere_touches_box on the padded voxel, with the
  // squared distances per axis computed once per plane and rows the sphere misses skipped: a large
  // sphere's bounding box is mostly voxels inside it.
  auto register_sphere = [&](const Primitive& p, uint32_t id, const int* lo, const int* hi,
                             std::vector<Ref>& refs) {
    const Vec3 c = p.p0;
    const double r2 = p.r0 * p.r0;
    double near[3][2048], far[3][2048];  // per axis, per voxel of the bounding box
    bool fits = true;
    for (int a = 0; a < 3; ++a) fits = fits && hi[a] - lo[a] < 2048;
    if (!fits) {  // an axis of more than 2048 voxels: voxel by voxel
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) {
            const Aabb vb = padded_voxel_box(g, x, y, z);
            if (vb.overlaps(p.bounds) && sphere_touches_box(c, p.r0, vb))
              refs.emplace_back(uint32_t(g.index(x, y, z)), id);
          }
      return;
    }
    double extent = 0;
    for (int a = 0; a < 3; ++a) {
      extent = std::max(extent, g.cell[a] * (1 + 2 * kVoxelPad));
      for (int i = lo[a]; i <= hi[a]; ++i) {
        const double l = g.plane(a, i) - kVoxelPad * g.cell[a] - c[a],
                     h = g.plane(a, i + 1) + kVoxelPad * g.cell[a] - c[a];
        const double n = l > 0 ? l : (h < 0 ? -h : 0);
        near[a][i - lo[a]] = n * n;
        far[a][i - lo[a]] = std::max(l * l, h * h);
      }
    }
    const double scale = max_abs(c) + p.r0 + extent;
    const double slack = 1e-12 * scale * scale;  // as sphere_touches_box
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y) {
        const double n_yz = near[2][z - lo[2]] + near[1][y - lo[1]];
        if (n_yz > r2 + slack) continue;
        const double f_yz = far[2][z - lo[2]] + far[1][y - lo[1]];
        const int64_t row = g.index(0, y, z);
        for (int x = lo[0]; x <= hi[0]; ++x)
          if (n_yz + near[0][x - lo[0]] <= r2 + slack && f_yz + far[0][x - lo[0]] >= r2 - slack)
            refs.emplace_back(uint32_t(row + x), id);
      }
  };
  // The first range's thread speaks for all: the ranges are of equal length.
  auto register_range = [&](size_t first, size_t last, std::vector<Ref>& refs, size_t ranges) {
    for (size_t i = first; i < last; ++i) {
      if (ranges && (i - first) % 1024 == 0)
        tell("voxelisation", "primitive", (i - first) * ranges, prims.size());
      const uint32_t id = uint32_t(i);
      const Primitive& p = prims[i];
      const bool sphere = opt.exact_spheres && p.kind == ShapeKind::Sphere && p.clips.empty();
      int lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::clamp(int(std::floor((p.bounds.lo[a] - g.box.lo[a]) / g.cell[a])) - 1, 0,
                           g.n[a] - 1);
        hi[a] = std::clamp(int(std::floor((p.bounds.hi[a] - g.box.lo[a]) / g.cell[a])) + 1, 0,
                           g.n[a] - 1);
      }
      if (sphere) {
        register_sphere(p, id, lo, hi, refs);
        continue;
      }
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) {
            const Aabb vb = padded_voxel_box(g, x, y, z);
            if (!vb.overlaps(p.bounds)) continue;
            bool touches = quadric_may_vanish(p.q, vb);
            for (size_t k = 0; touches && k < p.clips.size(); ++k)
              touches = box_touches_halfspace(vb, p.clips[k]);
            if (touches) refs.emplace_back(uint32_t(g.index(x, y, z)), id);
          }
    }
  };
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  // A thread is worth starting for a few hundred primitives at least.
  const size_t chunks = std::max<size_t>(1, std::min<size_t>(size_t(threads), prims.size() / 256));
  std::vector<std::vector<Ref>> refs(chunks);
  {
    std::vector<std::thread> pool;
    for (size_t c = 1; c < chunks; ++c)
      pool.emplace_back(register_range, prims.size() * c / chunks, prims.size() * (c + 1) / chunks,
                        std::ref(refs[c]), size_t(0));
    register_range(0, prims.size() / chunks, refs[0], chunks);
    for (std::thread& t : pool) t.join();
  }
  size_t total = 0;
  for (const auto& r : refs) total += r.size();
  if (total > UINT32_MAX) throw std::invalid_argument("grid holds too many primitive references");
  tell("grid build", "", 0, 0);  // sorting the references by voxel
  // start[v] counts, then ends, then (filling backwards) begins voxel v's list: no second array
  // the size of the grid.
  g.start.assign(size_t(g.voxel_count()) + 1, 0);
  for (const auto& rs : refs)
    for (const Ref& r : rs) ++g.start[r.first];
  for (size_t v = 1; v + 1 < g.start.size(); ++v) g.start[v] += g.start[v - 1];
  g.start.back() = uint32_t(total);
  g.items.resize(total);
  for (auto c = refs.rbegin(); c != refs.rend(); ++c)
    for (auto r = c->rbegin(); r != c->rend(); ++r) g.items[--g.start[r->first]] = r->second;
  return g;
}

}  // namespace rtm
