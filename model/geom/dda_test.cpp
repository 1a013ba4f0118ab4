// 3DDDA: visit sequences against an independent reference walk.
//
// The reference does not step: it collects every parameter where the ray crosses a voxel plane,
// sorts them, and names the voxel of each segment by counting the planes crossed so far. Its
// segments of positive length must be exactly the DDA's visits of positive length, in order,
// with the same windows; zero-length visits (edges and corners) are allowed between them.
#include "geom/dda.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>
#include "geom/test_random.h"

namespace rtm {
namespace {

using namespace rtm::test;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A grid with no voxel lists (the DDA needs only the geometry).
Grid make_grid(const Vec3& lo, const Vec3& cell, std::array<int, 3> n) {
  Grid g;
  g.n = n;
  g.cell = cell;
  g.box = Aabb{lo, {lo.x + n[0] * cell.x, lo.y + n[1] * cell.y, lo.z + n[2] * cell.z}};
  return g;
}

struct Visit {
  std::array<int, 3> cell;
  double t0, t1;
  bool last;  ///< is_last() before advancing
};

std::vector<Visit> walk(const Grid& g, const Vec3& o, const Vec3& d, double t_min, double t_max,
                        size_t limit = 1 << 20) {
  std::vector<Visit> out;
  for (DdaState s = Dda::start(g, o, d, t_min, t_max); !s.done; Dda::advance(g, o, d, t_max, s)) {
    out.push_back({s.cell, s.t_enter, s.t_exit, Dda::is_last(g, d, t_max, s)});
    if (out.size() > limit) break;  // a runaway walk fails the count checks instead of hanging
  }
  return out;
}

/// Entry and exit of the box by slabs, within [t_min, t_max]; false if the ray misses.
bool clip_to_box(const Grid& g, const Vec3& o, const Vec3& d, double t_min, double t_max,
                 double& t0, double& t1) {
  t0 = t_min;
  t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (o[a] < g.box.lo[a] || o[a] > g.box.hi[a]) return false;
      continue;
    }
    double ta = (g.box.lo[a] - o[a]) / d[a], tb = (g.box.hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

/// The reference: segments of positive length (longer than min_len) with their voxels.
std::vector<Visit> reference_walk(const Grid& g, const Vec3& o, const Vec3& d, double t_min,
                                  double t_max, double min_len) {
  double t0, t1;
  if (!clip_to_box(g, o, d, t_min, t_max, t0, t1)) return {};
  std::vector<double> cross[3];
  std::vector<double> bp = {t0, t1};
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) continue;
    for (int j = 1; j < g.n[a]; ++j) {
      const double t = (g.plane(a, j) - o[a]) / d[a];
      cross[a].push_back(t);
      if (t > t0 && t < t1) bp.push_back(t);
    }
  }
  std::sort(bp.begin(), bp.end());
  std::vector<Visit> out;
  for (size_t k = 0; k + 1 < bp.size(); ++k) {
    if (!(bp[k + 1] - bp[k] > min_len)) continue;
    Visit v{{0, 0, 0}, bp[k], bp[k + 1], false};
    const double mid = bp[k] + (bp[k + 1] - bp[k]) / 2;
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0) {
        v.cell[a] = std::clamp(int(std::floor((o[a] - g.box.lo[a]) / g.cell[a])), 0, g.n[a] - 1);
        continue;
      }
      // Planes crossed before the middle of the segment.
      const int crossed =
          int(std::count_if(cross[a].begin(), cross[a].end(), [&](double t) { return t < mid; }));
      v.cell[a] = d[a] > 0 ? crossed : g.n[a] - 1 - crossed;
    }
    out.push_back(v);
  }
  if (!out.empty()) out.back().last = true;
  return out;
}

/// Structural checks on any walk, then the comparison with the reference.
void check_walk(const Grid& g, const Vec3& o, const Vec3& d, double t_min, double t_max,
                const char* what = "") {
  SCOPED_TRACE(::testing::Message()
               << what << " o = (" << o.x << ", " << o.y << ", " << o.z << ") d = (" << d.x << ", "
               << d.y << ", " << d.z << ") t in [" << t_min << ", " << t_max << "]");
  const std::vector<Visit> w = walk(g, o, d, t_min, t_max);
  double t0, t1;
  const bool hits = clip_to_box(g, o, d, t_min, t_max, t0, t1);
  if (!hits) {
    ASSERT_TRUE(w.empty()) << "a ray missing the grid visited " << w.size() << " voxels";
    return;
  }
  ASSERT_FALSE(w.empty()) << "a ray meeting the grid visited nothing";
  ASSERT_LE(w.size(), size_t(g.n[0] + g.n[1] + g.n[2]));
  EXPECT_EQ(w.front().t0, t0) << "the walk does not start where the ray enters";
  for (size_t i = 0; i < w.size(); ++i) {
    const Visit& v = w[i];
    for (int a = 0; a < 3; ++a) {
      ASSERT_GE(v.cell[a], 0);
      ASSERT_LT(v.cell[a], g.n[a]);
    }
    ASSERT_LE(v.t0, v.t1) << "visit " << i;
    ASSERT_LE(v.t0, t_max) << "visit " << i << " starts past t_max";
    ASSERT_EQ(v.last, i + 1 == w.size()) << "is_last() wrong at visit " << i << " of " << w.size();
    if (i == 0) continue;
    const Visit& u = w[i - 1];
    ASSERT_EQ(u.t1, v.t0) << "windows not contiguous at visit " << i;
    // 6-connected, one step on one axis, in the direction of travel, never on a zero axis.
    int steps = 0;
    for (int a = 0; a < 3; ++a) {
      const int dc = v.cell[a] - u.cell[a];
      if (dc == 0) continue;
      ++steps;
      ASSERT_EQ(std::abs(dc), 1);
      ASSERT_NE(d[a], 0.0);
      ASSERT_EQ(dc > 0, d[a] > 0) << "stepped against the ray on axis " << a;
    }
    ASSERT_EQ(steps, 1) << "visit " << i;
  }
  // The walk covers the ray up to where it leaves the grid or reaches t_max.
  const double scale = std::max({std::abs(t0), std::abs(t1), 1.0});
  if (std::isfinite(t1)) {
    ASSERT_GE(w.back().t1, t1 - 1e-9 * scale);
  }

  // Positive-length visits against the reference.
  const double min_len =
      1e-9 * std::max({std::abs(t0), std::isfinite(t1) ? std::abs(t1) : 0.0, 1e-300});
  std::vector<Visit> got;
  for (const Visit& v : w)
    if (std::min(v.t1, t1) - v.t0 > min_len) got.push_back(v);
  const std::vector<Visit> ref = reference_walk(g, o, d, t_min, t_max, min_len);
  ASSERT_EQ(got.size(), ref.size()) << "positive-length visits differ in number";
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(got[i].cell, ref[i].cell)
        << "visit " << i << ": (" << got[i].cell[0] << ", " << got[i].cell[1] << ", "
        << got[i].cell[2] << ") vs reference (" << ref[i].cell[0] << ", " << ref[i].cell[1] << ", "
        << ref[i].cell[2] << ")";
    ASSERT_NEAR(got[i].t0, ref[i].t0, 1e-12 * scale) << "visit " << i;
    ASSERT_NEAR(std::min(got[i].t1, t1), ref[i].t1, 1e-12 * scale) << "visit " << i;
  }
}

// ---------------------------------------------------------------------------------------------

TEST(DdaWalk, AxisParallelBothWaysWithSignedZeros) {
  const Grid g = make_grid({0, 0, 0}, {1, 1, 1}, {8, 8, 8});
  for (double zero : {0.0, -0.0}) {
    // +x: (0..7, 2, 5), windows [1 + i, 2 + i].
    std::vector<Visit> w = walk(g, {-1, 2.5, 5.5}, {1, zero, -zero}, 0, kInf);
    ASSERT_EQ(w.size(), 8u);
    for (int i = 0; i < 8; ++i) {
      EXPECT_EQ(w[size_t(i)].cell, (std::array<int, 3>{i, 2, 5}));
      EXPECT_EQ(w[size_t(i)].t0, 1 + i);
      EXPECT_EQ(w[size_t(i)].t1, 2 + i);
      EXPECT_EQ(w[size_t(i)].last, i == 7);
    }
    // −y: (3, 7..0, 6).
    w = walk(g, {3.5, 9.5, 6.5}, {-zero, -1, zero}, 0, kInf);
    ASSERT_EQ(w.size(), 8u);
    for (int i = 0; i < 8; ++i) {
      EXPECT_EQ(w[size_t(i)].cell, (std::array<int, 3>{3, 7 - i, 6}));
      EXPECT_EQ(w[size_t(i)].t0, 1.5 + i);
    }
    // ±z.
    for (double dir : {1.0, -1.0}) {
      check_walk(g, {4.25, 0.75, dir > 0 ? -3.0 : 11.0}, {zero, zero, dir}, 0, kInf, "z");
      EXPECT_EQ(walk(g, {4.25, 0.75, dir > 0 ? -3.0 : 11.0}, {zero, zero, dir}, 0, kInf).size(),
                8u);
    }
    check_walk(g, {-1, 2.5, 5.5}, {1, zero, -zero}, 0, kInf, "+x");
    check_walk(g, {9, 2.5, 5.5}, {-1, -zero, zero}, 0, kInf, "-x");
    check_walk(g, {3.5, 9.5, 6.5}, {-zero, -1, zero}, 0, kInf, "-y");
  }
}

TEST(DdaWalk, DiagonalThroughCorners) {
  // d = (1,1,1) through voxel corners: the positive-length voxels are (i,i,i); at each corner the
  // lowest axis steps first, giving two zero-length voxels (i+1,i,i), (i+1,i+1,i).
  const Grid g = make_grid({0, 0, 0}, {1, 1, 1}, {8, 8, 8});
  for (int sign : {1, -1}) {
    const Vec3 o = sign > 0 ? Vec3(-0.5) : Vec3(8.5), d = Vec3(double(sign));
    const std::vector<Visit> w = walk(g, o, d, 0, kInf);
    ASSERT_EQ(w.size(), 8u + 2 * 7u);
    int positive = 0;
    for (size_t i = 0; i < w.size(); ++i) {
      const int k = int(i) / 3;
      const int c = sign > 0 ? k : 7 - k;
      const int s = sign > 0 ? 1 : -1;
      std::array<int, 3> expect{c, c, c};
      if (i % 3 == 1) expect = {c + s, c, c};
      if (i % 3 == 2) expect = {c + s, c + s, c};
      EXPECT_EQ(w[i].cell, expect) << i;
      if (i % 3 == 0) {
        ++positive;
        EXPECT_EQ(w[i].t0, 0.5 + k);
        EXPECT_EQ(w[i].t1, 1.5 + k);
      } else {
        EXPECT_EQ(w[i].t0, w[i].t1) << "corner voxels have zero length";
      }
    }
    EXPECT_EQ(positive, 8);
    check_walk(g, o, d, 0, kInf, "diagonal");
  }
}

TEST(DdaWalk, GrazingEdgesAndFaces) {
  const Grid g = make_grid({0, 0, 0}, {1, 1, 1}, {8, 8, 8});
  // Through voxel edges in the xy plane: (i,i,3) with one zero-length (i+1,i,3) at each edge.
  std::vector<Visit> w = walk(g, {-0.5, -0.5, 3.5}, {1, 1, 0}, 0, kInf);
  ASSERT_EQ(w.size(), 15u);
  for (size_t i = 0; i < w.size(); ++i) {
    const int k = int(i) / 2;
    EXPECT_EQ(w[i].cell, (i % 2 ? std::array<int, 3>{k + 1, k, 3} : std::array<int, 3>{k, k, 3}));
  }
  check_walk(g, {-0.5, -0.5, 3.5}, {1, 1, 0}, 0, kInf, "edge");
  check_walk(g, {8.5, -0.5, 3.5}, {-1, 1, -0.0}, 0, kInf, "edge, mirrored");
  // Along an interior face y = 4: one row of voxels, all on the same side.
  w = walk(g, {-1, 4, 2.5}, {1, 0, 0}, 0, kInf);
  ASSERT_EQ(w.size(), 8u);
  for (const Visit& v : w) {
    EXPECT_EQ(v.cell[1], w[0].cell[1]);
    EXPECT_TRUE(v.cell[1] == 3 || v.cell[1] == 4);
  }
  // Along the grid's outer face y = 8 (touching the grid): the boundary row.
  w = walk(g, {-1, 8, 2.5}, {1, 0, 0}, 0, kInf);
  ASSERT_EQ(w.size(), 8u);
  EXPECT_EQ(w[0].cell[1], 7);
  // Just outside it: nothing.
  EXPECT_TRUE(walk(g, {-1, std::nextafter(8.0, 9.0), 2.5}, {1, 0, 0}, 0, kInf).empty());
  // Through the grid's corner (8,8,8) from outside, touching only that point.
  w = walk(g, {9, 9, 7}, {-1, -1, 1}, 0, kInf);
  ASSERT_LE(w.size(), 1u);
  for (const Visit& v : w) EXPECT_EQ(v.t0, v.t1);
}

TEST(DdaWalk, StartsInsideOutsideOnTheBoundaryAndMisses) {
  const Grid g = make_grid({0, 0, 0}, {1, 1, 1}, {8, 8, 8});
  // Inside: the first voxel holds the origin, from t = 0.
  std::vector<Visit> w = walk(g, {3.3, 4.7, 1.2}, normalize(Vec3{0.3, -0.5, 0.8}), 0, kInf);
  ASSERT_FALSE(w.empty());
  EXPECT_EQ(w[0].cell, (std::array<int, 3>{3, 4, 1}));
  EXPECT_EQ(w[0].t0, 0);
  check_walk(g, {3.3, 4.7, 1.2}, normalize(Vec3{0.3, -0.5, 0.8}), 0, kInf, "inside");
  // On the boundary, pointing in: from t = 0 across the grid.
  w = walk(g, {0, 3.5, 3.5}, {1, 0, 0}, 0, kInf);
  ASSERT_EQ(w.size(), 8u);
  EXPECT_EQ(w[0].t0, 0);
  w = walk(g, {8, 3.5, 3.5}, {-1, 0, 0}, 0, kInf);
  ASSERT_EQ(w.size(), 8u);
  EXPECT_EQ(w[0].cell[0], 7);
  // On the boundary, pointing out: at most the touching point, with zero length.
  w = walk(g, {8, 3.5, 3.5}, {1, 0, 0}, 0, kInf);
  ASSERT_LE(w.size(), 1u);
  for (const Visit& v : w) EXPECT_EQ(v.t0, v.t1);
  EXPECT_TRUE(walk(g, {std::nextafter(8.0, 9.0), 3.5, 3.5}, {1, 0, 0}, 0, kInf).empty());
  // Outside and missing, or pointing away.
  EXPECT_TRUE(walk(g, {-1, 9, 3}, {1, 0, 0}, 0, kInf).empty());
  EXPECT_TRUE(walk(g, {-1, -1, -1}, normalize(Vec3{-1, 0.2, 0.3}), 0, kInf).empty());
  EXPECT_TRUE(walk(g, {-1, 4, 4}, {-1, 0, 0}, 0, kInf).empty());
  EXPECT_TRUE(walk(g, {-2, 7, 4}, normalize(Vec3{1, 1, 0}), 0, kInf).empty());  // passes the corner
  EXPECT_TRUE(walk(g, {4, 4, 4}, {1, 0, 0}, 10, kInf).empty());  // t_min past the exit
  for (const Vec3& o : {Vec3{-1, 9, 3}, Vec3{-1, -1, -1}, Vec3{-2, 7, 4}})
    check_walk(g, o, {1, 0, 0}, 0, kInf, "miss");
}

TEST(DdaWalk, TminAndShadowTmax) {
  const Grid g = make_grid({0, 0, 0}, {1, 1, 1}, {8, 8, 8});
  // A shadow ray to a light at t = 2.4 from x = 0.5: voxels 0, 1, 2 and no further.
  std::vector<Visit> w = walk(g, {0.5, 0.5, 0.5}, {1, 0, 0}, 0, 2.4);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w.back().cell[0], 2);
  EXPECT_TRUE(w.back().last);
  EXPECT_LE(w.back().t0, 2.4);
  EXPECT_GE(w.back().t1, 2.4);
  // t_max before the grid: nothing.
  EXPECT_TRUE(walk(g, {-5, 4, 4}, {1, 0, 0}, 0, 3).empty());
  // t_min: the walk starts at the voxel of o + t_min d.
  w = walk(g, {-5, 4.5, 4.5}, {1, 0, 0}, 7.25, kInf);
  ASSERT_EQ(w.size(), 6u);
  EXPECT_EQ(w[0].cell[0], 2);
  EXPECT_EQ(w[0].t0, 7.25);
  std::mt19937 rng(50);
  for (int i = 0; i < 500; ++i) {
    const Vec3 o{uniform(rng, -4, 12), uniform(rng, -4, 12), uniform(rng, -4, 12)};
    const Vec3 d = random_unit(rng);
    const double t_min = uniform(rng, 0, 3), t_max = t_min + uniform(rng, 0, 10);
    check_walk(g, o, d, t_min, t_max, "window");
  }
}

TEST(DdaWalk, LongWalksTerminateWithTheRightCount) {
  // 4096 voxels on x, cell 3.7/4096 (not a power of two): planes from the index do not drift.
  const Grid g = make_grid({-1.3, 0, 0}, {3.7 / 4096, 1, 1}, {4096, 1, 1});
  for (double dir : {1.0, -1.0}) {
    const Vec3 o{dir > 0 ? -2.0 : 3.0, 0.5, 0.5};
    const std::vector<Visit> w = walk(g, o, {dir, 0, 0}, 0, kInf);
    ASSERT_EQ(w.size(), 4096u);
    for (size_t i = 0; i < w.size(); ++i) ASSERT_EQ(w[i].cell[0], dir > 0 ? int(i) : 4095 - int(i));
    check_walk(g, o, {dir, 0, 0}, 0, kInf, "long x");
    // Slightly tilted, staying in the slab.
    check_walk(g, o, normalize(Vec3{dir, 1e-5, -1e-5}), 0, kInf, "long x, tilted");
    EXPECT_EQ(walk(g, o, normalize(Vec3{dir, 1e-5, -1e-5}), 0, kInf).size(), 4096u);
  }
  // A long 3D walk.
  const Grid big = make_grid({0, 0, 0}, {1.0 / 512, 1.0 / 512, 1.0 / 512}, {512, 512, 512});
  std::mt19937 rng(51);
  for (int i = 0; i < 20; ++i) {
    const Vec3 d = random_unit(rng);
    const Vec3 o = Vec3(0.5) - 2.0 * d;
    check_walk(big, o, d, 0, kInf, "long 3D");
    EXPECT_GT(walk(big, o, d, 0, kInf).size(), 512u);
  }
}

TEST(DdaWalk, RandomRaysAgainstReference) {
  std::mt19937 rng(52);
  for (int i = 0; i < 4000; ++i) {
    const std::array<int, 3> n{1 + int(rng() % 24), 1 + int(rng() % 24), 1 + int(rng() % 24)};
    const Vec3 lo{uniform(rng, -100, 100), uniform(rng, -100, 100), uniform(rng, -100, 100)};
    const double unit = std::pow(10.0, uniform(rng, -2, 1));
    const Vec3 cell{unit * uniform(rng, 0.3, 3), unit * uniform(rng, 0.3, 3),
                    unit * uniform(rng, 0.3, 3)};
    const Grid g = make_grid(lo, cell, n);
    const Vec3 e = g.box.extent();
    Vec3 o;
    switch (i % 3) {
      case 0:  // inside
        o = g.box.lo + uniform_zyx(rng, 0, 1) * e;
        break;
      case 1:  // outside, near
        o = g.box.lo + uniform_zyx(rng, -1, 2) * e;
        break;
      default: {  // on a face
        o = g.box.lo + uniform_zyx(rng, 0, 1) * e;
        const int a = int(rng() % 3);
        o[a] = rng() % 2 ? g.box.lo[a] : g.box.hi[a];
      }
    }
    Vec3 d = random_unit(rng);
    if (rng() % 4 == 0) d = normalize(g.box.lo + 0.5 * e - o);  // aimed at the centre
    if (rng() % 4 == 0) d[int(rng() % 3)] = rng() % 2 ? 0.0 : -0.0;
    if (rng() % 8 == 0) d[int(rng() % 3)] = rng() % 2 ? 0.0 : -0.0;
    if (d == Vec3{0, 0, 0}) continue;
    d *= std::pow(10.0, uniform(rng, -2, 2));  // directions need not be unit
    double t_min = 0, t_max = kInf;
    if (rng() % 5 == 0) t_min = uniform(rng, 0, 1) * length(e) / length(d);
    if (rng() % 5 == 0) t_max = t_min + uniform(rng, 0, 2) * length(e) / length(d);
    check_walk(g, o, d, t_min, t_max, "random");
    if (::testing::Test::HasFatalFailure()) {
      ADD_FAILURE() << "case " << i;
      return;
    }
  }
}

TEST(DdaWalk, NonFiniteInputsVisitNothing) {
  const Grid g = make_grid({0, 0, 0}, {1, 1, 1}, {8, 8, 8});
  EXPECT_TRUE(walk(g, {kNaN, 4, 4}, {1, 0, 0}, 0, kInf).empty());
  EXPECT_TRUE(walk(g, {4, kNaN, 4}, {1, 0, 0}, 0, kInf).empty());  // NaN on a zero-direction axis
  EXPECT_TRUE(walk(g, {4, 4, 4}, {1, kNaN, 0}, 0, kInf).empty());
  EXPECT_TRUE(walk(g, {-kInf, 4, 4}, {1, 0, 0}, 0, kInf).empty());
  EXPECT_TRUE(walk(g, {4, 4, 4}, {kInf, 0, 0}, 0, kInf).empty());
  EXPECT_TRUE(walk(g, {4, 4, 4}, {1, 0, 0}, kNaN, kInf).empty());
  EXPECT_TRUE(walk(g, {4, 4, 4}, {1, 0, 0}, 0, kNaN).empty());
}

// ---------------------------------------------------------------------------------------------
// Against an exact rational walk (docs/numerics.md, case 10)
//
// Every coordinate is an integer number of units u = 2⁻⁸ and every direction component a small
// integer, so each crossing time (plane − o)/d is a ratio of integers: the reference compares
// them exactly (__int128 cross-multiplication), applies the DDA's rules (ties step the lowest axis
// first, zero-length voxels included, stop when the index leaves the grid) and must produce the
// DDA's visits one for one: same voxels, and windows equal to the correctly rounded exact times.
// With these magnitudes two different crossing times differ by far more than an ulp, so nothing
// may differ at all, however long the walk (4096 voxels per axis) and wherever the grid sits.

constexpr double kUnit = 1.0 / 256;

struct ExactRay {
  std::array<int64_t, 3> lo, cell, o;                 ///< grid corner, voxel edge, origin: in units
  std::array<int64_t, 3> d;                           ///< direction components (integers)
  std::array<bool, 3> neg_zero{false, false, false};  ///< a zero component written as −0.0
  std::array<int, 3> n;
};

struct Rat {
  __int128 num = 0, den = 1;  ///< den > 0; den == 0: +infinity
};
bool rat_less(const Rat& a, const Rat& b) {
  if (b.den == 0) return a.den != 0;
  if (a.den == 0) return false;
  return a.num * b.den < b.num * a.den;
}
const Rat& rat_max(const Rat& a, const Rat& b) { return rat_less(a, b) ? b : a; }
/// The time as the DDA computes it: (plane − o) in world units, divided by d, rounded once.
double rat_double(const Rat& r) {
  return r.den == 0 ? kInf : (double(int64_t(r.num)) * kUnit) / double(int64_t(r.den));
}

Rat crossing_exact(const ExactRay& e, int a, int64_t boundary) {
  if (e.d[a] == 0) return {0, 0};
  const __int128 num = __int128(e.lo[a]) + __int128(boundary) * e.cell[a] - e.o[a];
  return e.d[a] > 0 ? Rat{num, e.d[a]} : Rat{-num, -e.d[a]};
}

__int128 floor_div(__int128 a, __int128 b) {  // b > 0
  __int128 q = a / b;
  if (a % b != 0 && a < 0) --q;
  return q;
}

std::vector<Visit> exact_walk(const ExactRay& e) {
  std::vector<Visit> out;
  // Entry and exit of the box by slabs, from t = 0.
  Rat t0{0, 1}, t1{0, 0};
  for (int a = 0; a < 3; ++a) {
    const int64_t hi = e.lo[a] + e.n[a] * e.cell[a];
    if (e.d[a] == 0) {
      if (e.o[a] < e.lo[a] || e.o[a] > hi) return out;
      continue;
    }
    Rat ta = crossing_exact(e, a, 0), tb = crossing_exact(e, a, e.n[a]);
    if (rat_less(tb, ta)) std::swap(ta, tb);
    t0 = rat_max(t0, ta);
    if (rat_less(tb, t1)) t1 = tb;
  }
  if (rat_less(t1, t0)) return out;
  std::array<int, 3> cell{};
  for (int a = 0; a < 3; ++a) {
    // Position o + t0 d in units, as a fraction over t0.den: floor((p − lo) / cell).
    const __int128 p_num = __int128(e.o[a]) * t0.den + t0.num * e.d[a] - __int128(e.lo[a]) * t0.den;
    const __int128 c = floor_div(p_num, __int128(e.cell[a]) * t0.den);
    cell[a] = int(std::clamp<__int128>(c, 0, e.n[a] - 1));
  }
  std::array<Rat, 3> next;
  auto crossing_of = [&](int a) {
    return crossing_exact(e, a, e.d[a] > 0 ? cell[a] + 1 : cell[a]);
  };
  auto exit_axis = [&] {
    int a = 0;
    if (rat_less(next[1], next[a])) a = 1;
    if (rat_less(next[2], next[a])) a = 2;
    return a;
  };
  for (int a = 0; a < 3; ++a) next[size_t(a)] = crossing_of(a);
  Rat enter = t0, exit = rat_max(t0, next[size_t(exit_axis())]);
  for (;;) {
    const int a = exit_axis();
    const bool infinite = next[size_t(a)].den == 0;
    const int step = cell[a] + (e.d[a] > 0 ? 1 : -1);
    out.push_back(
        {cell, rat_double(enter), rat_double(exit), infinite || step < 0 || step >= e.n[a]});
    if (out.back().last) return out;
    cell[a] = step;
    enter = exit;
    next[size_t(a)] = crossing_of(a);
    exit = rat_max(enter, next[size_t(exit_axis())]);
  }
}

Grid exact_grid(const ExactRay& e) {
  return make_grid({e.lo[0] * kUnit, e.lo[1] * kUnit, e.lo[2] * kUnit},
                   {e.cell[0] * kUnit, e.cell[1] * kUnit, e.cell[2] * kUnit}, e.n);
}

void check_exact(const ExactRay& e, const char* what) {
  const Grid g = exact_grid(e);
  Vec3 o, d;
  for (int a = 0; a < 3; ++a) {
    o[a] = double(e.o[a]) * kUnit;
    d[a] = e.d[a] == 0 && e.neg_zero[size_t(a)] ? -0.0 : double(e.d[a]);
  }
  SCOPED_TRACE(::testing::Message() << what << " o = (" << o.x << ", " << o.y << ", " << o.z
                                    << ") d = (" << d.x << ", " << d.y << ", " << d.z << ")");
  const std::vector<Visit> got = walk(g, o, d, 0, kInf);
  const std::vector<Visit> ref = exact_walk(e);
  ASSERT_LE(got.size(), size_t(e.n[0] + e.n[1] + e.n[2]))
      << "a walk is at most nx + ny + nz voxels";
  ASSERT_EQ(got.size(), ref.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(got[i].cell, ref[i].cell) << "visit " << i;
    ASSERT_EQ(got[i].t0, ref[i].t0) << "visit " << i;
    ASSERT_EQ(got[i].t1, ref[i].t1) << "visit " << i;
    ASSERT_EQ(got[i].last, ref[i].last) << "visit " << i;
  }
}

TEST(DdaExact, LongWalksOn4096CubedMatchTheRationalWalkVisitForVisit) {
  std::mt19937 rng(60);
  const std::array<int, 3> n{4096, 4096, 4096};
  int visits = 0;
  for (int i = 0; i < 120; ++i) {
    ExactRay e;
    e.n = n;
    for (int a = 0; a < 3; ++a) {
      e.cell[size_t(a)] = 1 + int64_t(rng() % 5);  // not powers of two: 1 … 5 units
      // The grid's corner at the origin, 1e3, 1e4 or 1e5 away (all exact in units).
      e.lo[size_t(a)] = int64_t(std::array<double, 4>{0, 1e3, -1e4, 1e5}[size_t(i % 4)] / kUnit) +
                        int64_t(rng() % 64);
      e.d[size_t(a)] = int64_t(rng() % 4097) - 2048;
    }
    if (i % 5 == 0) e.d = {1, 1, 1};                     // through voxel corners
    if (i % 5 == 1) e.d[size_t(rng() % 3)] = 0;          // in a plane of the grid
    if (i % 7 == 2) e.d = {0, 0, (rng() & 1) ? 1 : -1};  // axis-parallel
    if (e.d == std::array<int64_t, 3>{0, 0, 0}) e.d = {1, 0, 0};
    for (int a = 0; a < 3; ++a) e.neg_zero[size_t(a)] = rng() & 1;
    for (int a = 0; a < 3; ++a) {
      const int64_t size = e.n[a] * e.cell[size_t(a)];
      switch (i % 3) {
        case 0: {  // inside, on voxel planes as often as not
          // One draw a statement: the order of calls within one expression is unspecified.
          const int64_t at = int64_t(rng() % uint64_t(size + 1));
          const int64_t down = (rng() & 1) ? e.cell[size_t(a)] : 1;
          const int64_t up = (rng() & 1) ? e.cell[size_t(a)] : 1;
          e.o[size_t(a)] = e.lo[size_t(a)] + at / down * up;
          break;
        }
        case 1:  // on the boundary of the grid
          e.o[size_t(a)] = e.lo[size_t(a)] + ((rng() & 1) ? 0 : size);
          break;
        default:  // outside, up to a grid away
          e.o[size_t(a)] = e.lo[size_t(a)] - size + int64_t(rng() % uint64_t(3 * size));
      }
    }
    check_exact(e, "random");
    if (::testing::Test::HasFatalFailure()) return;
    visits += int(exact_walk(e).size());
  }
  EXPECT_GT(visits, 120 * 1000) << "the walks are long";
}

TEST(DdaExact, CornerEdgeAndBoundaryCasesMatchTheRationalWalk) {
  const std::array<int, 3> n{4096, 4096, 4096};
  ExactRay e;
  e.n = n;
  e.cell = {4, 4, 4};
  e.lo = {int64_t(1e5 / kUnit), int64_t(-1e4 / kUnit), 0};
  const int64_t size = 4096 * 4;
  // Along a grid edge (the line where two planes of voxel faces meet), both ways, with ±0.0.
  for (int64_t dir : {1, -1})
    for (bool nz : {false, true}) {
      e.o = {e.lo[0] + 8, e.lo[1] + 12, dir > 0 ? e.lo[2] - 3 : e.lo[2] + size + 3};
      e.d = {0, 0, dir};
      e.neg_zero = {nz, !nz, nz};
      check_exact(e, "along an edge");
      EXPECT_EQ(exact_walk(e).size(), 4096u);
    }
  // Exactly through every corner of the main diagonal, from outside, from the corner itself and
  // from the far corner backwards.
  for (int64_t start : {-5, 0})
    for (int64_t dir : {1, -1}) {
      const int64_t s = dir > 0 ? start : size - start;
      e.o = {e.lo[0] + s, e.lo[1] + s, e.lo[2] + s};
      e.d = {dir, dir, dir};
      check_exact(e, "diagonal");
      EXPECT_EQ(exact_walk(e).size(),
                3u * 4096 - 2);  // 4096 voxels and two zero-length ones per corner
    }
  // Starting on each face of the grid, pointing in and pointing out.
  for (int a = 0; a < 3; ++a)
    for (int64_t side : {0, 1})
      for (int64_t dir : {1, -1}) {
        e.o = {e.lo[0] + 4 * 1000 + 1, e.lo[1] + 4 * 2000 + 2, e.lo[2] + 4 * 3000 + 3};
        e.o[size_t(a)] = e.lo[size_t(a)] + side * size;
        e.d = {3, -7, 11};
        e.d[size_t(a)] = dir * 5;
        check_exact(e, "on a face");
      }
}

}  // namespace
}  // namespace rtm

namespace rtm {
namespace {

bool same_state(const DdaState& a, const DdaState& b) {
  return a.cell == b.cell && a.t_next == b.t_next && a.t_enter == b.t_enter &&
         a.t_exit == b.t_exit && a.done == b.done;
}

bool inside(const std::array<int, 3>& c, const std::array<int, 3>& lo,
            const std::array<int, 3>& hi) {
  for (int a = 0; a < 3; ++a)
    if (c[a] < lo[a] || c[a] > hi[a]) return false;
  return true;
}

/// skip_box against advance() one voxel at a time: from every voxel of the walk, over a random
/// box holding it, the skip must leave the state exactly where the steps do, having counted them.
void check_skips(const Grid& g, const Vec3& o, const Vec3& d, double t_max, std::mt19937& rng,
                 int& skipped) {
  SCOPED_TRACE(::testing::Message() << "o = (" << o.x << ", " << o.y << ", " << o.z << ") d = ("
                                    << d.x << ", " << d.y << ", " << d.z << ") t_max " << t_max);
  for (DdaState s = Dda::start(g, o, d, 0, t_max); !s.done; Dda::advance(g, o, d, t_max, s)) {
    std::array<int, 3> lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::uniform_int_distribution<int>(0, s.cell[a])(rng);
      hi[a] = std::uniform_int_distribution<int>(s.cell[a], g.n[a] - 1)(rng);
    }
    // Step until the next voxel is outside the box or the walk ends.
    DdaState stepped = s;
    int steps = 0;
    for (;;) {
      DdaState next = stepped;
      Dda::advance(g, o, d, t_max, next);
      if (!inside(next.cell, lo, hi))
        break;          // leaves the box (or the grid, through the box's face)
      if (next.done) {  // ends inside the box: no skip promised
        steps = -1;
        break;
      }
      stepped = next;
      ++steps;
    }
    DdaState skipped_state = s;
    const int k = Dda::skip_box(g, o, d, t_max, skipped_state, lo, hi);
    if (k == 0) {
      ASSERT_TRUE(same_state(skipped_state, s)) << "a skip of no voxels changed the state";
      ASSERT_TRUE(steps <= 0 || t_max < kInf)
          << "skipped nothing where " << steps << " steps stay in the box";
      continue;
    }
    ASSERT_EQ(k, steps) << "cell (" << s.cell[0] << ", " << s.cell[1] << ", " << s.cell[2] << ")";
    ASSERT_TRUE(same_state(skipped_state, stepped))
        << "after " << k << " steps from (" << s.cell[0] << ", " << s.cell[1] << ", " << s.cell[2]
        << ")";
    ++skipped;
  }
}

TEST(DdaSkipBox, LandsExactlyWhereTheStepsDoOnRandomRays) {
  std::mt19937 rng(7);
  int skipped = 0;
  for (int i = 0; i < 400; ++i) {
    const std::array<int, 3> n{1 + int(rng() % 40), 1 + int(rng() % 40), 1 + int(rng() % 40)};
    const Vec3 cell{test::log_uniform(rng, -2, 2), test::log_uniform(rng, -2, 2),
                    test::log_uniform(rng, -2, 2)};
    const Grid g = make_grid(
        {test::uniform(rng, -50, 50), test::uniform(rng, -50, 50), test::uniform(rng, -50, 50)},
        cell, n);
    const Vec3 o = g.box.lo + test::uniform_zyx(rng, -0.2, 1.2) * g.box.extent();
    Vec3 d = test::random_unit(rng);
    if (i % 5 == 0) d[rng() % 3] = (rng() & 1) ? 0.0 : -0.0;  // zero components never step
    const double t_max = i % 3 == 0 ? test::uniform(rng, 0, length(g.box.extent())) : kInf;
    check_skips(g, o, d, t_max, rng, skipped);
  }
  EXPECT_GT(skipped, 1000);
}

TEST(DdaAdvanceAhead, VisitsTheSameStatesAsAdvance) {
  std::mt19937 rng(13);
  int visits = 0;
  for (int i = 0; i < 300; ++i) {
    const std::array<int, 3> n{1 + int(rng() % 30), 1 + int(rng() % 30), 1 + int(rng() % 30)};
    const Vec3 cell{test::log_uniform(rng, -1, 1), test::log_uniform(rng, -1, 1),
                    test::log_uniform(rng, -1, 1)};
    const Grid g = make_grid(
        {test::uniform(rng, -5, 5), test::uniform(rng, -5, 5), test::uniform(rng, -5, 5)}, cell, n);
    const Vec3 o = g.box.lo + test::uniform_zyx(rng, -0.2, 1.2) * g.box.extent();
    Vec3 d =
        i % 7 == 0 ? Vec3(1, 1, i % 2) : test::random_unit(rng);  // some through edges and corners
    if (i % 5 == 0) d[rng() % 3] = 0.0;
    const double t_max = i % 3 == 0 ? test::uniform(rng, 0, length(g.box.extent())) : kInf;
    DdaState a = Dda::start(g, o, d, 0, t_max), b = a;
    std::array<double, 3> ahead = Dda::ahead(g, o, d, b);
    while (!a.done) {
      ASSERT_TRUE(same_state(a, b)) << "ray " << i << " visit " << visits;
      Dda::advance(g, o, d, t_max, a);
      Dda::advance_ahead(g, o, d, t_max, b, ahead);
      ++visits;
    }
    ASSERT_TRUE(b.done);
  }
  EXPECT_GT(visits, 1000);
}

TEST(DdaSkipBox, TiesAtEdgesAndCornersGoToTheLowerAxisAsInAdvance) {
  // Unit voxels, rays through lattice points: crossings on two or three axes coincide exactly.
  std::mt19937 rng(11);
  const Grid g = make_grid({0, 0, 0}, {1, 1, 1}, {16, 16, 16});
  int skipped = 0;
  for (const Vec3& d : {Vec3(1, 1, 0), Vec3(1, 1, 1), Vec3(-1, 1, 1), Vec3(1, -1, -1),
                        Vec3(2, 1, 0), Vec3(1, 2, 2), Vec3(-2, -2, 1), Vec3(0, -1, 1)})
    for (const Vec3& o :
         {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0.5), Vec3(3, 5, 7), Vec3(15.5, 0.25, 8), Vec3(16, 16, 0)})
      check_skips(g, o, d, kInf, rng, skipped);
  EXPECT_GT(skipped, 50);
}

// dda_precision: the same walk in float. Near a corner, float cannot tell which plane comes
// first: a ray aimed 1e-9 above the corner (1, 1) crosses y = 1 first in double, but its two
// direction components round to the same float, so in float both crossings tie and x goes first.
template <class Real>
std::vector<std::array<int, 3>> cells_of(const Grid& g, const Vec3& o, const Vec3& d) {
  std::vector<std::array<int, 3>> cells;
  for (DdaState s = BasicDda<Real>::start(g, o, d, 0, kInf); !s.done;
       BasicDda<Real>::advance(g, o, d, kInf, s)) {
    cells.push_back(s.cell);
    // The walk's times are Real's: a float walk's are floats, held exactly in the double state.
    for (double t : {s.t_enter, s.t_exit, s.t_next[0], s.t_next[1]}) EXPECT_EQ(double(Real(t)), t);
  }
  return cells;
}

TEST(DdaPrecision, Fp32AndFp64PartAtACornerFloatCannotResolve) {
  const Grid g = make_grid({0, 0, 0}, {1, 1, 1}, {4, 4, 1});
  const Vec3 o{0.1, 0.1, 0.5};
  const Vec3 d = normalize(Vec3{0.9, 0.9 + 1e-9, 0});
  ASSERT_EQ(float(d.x), float(d.y));
  const std::vector<std::array<int, 3>> c64 = cells_of<double>(g, o, d),
                                        c32 = cells_of<float>(g, o, d);
  ASSERT_GE(c64.size(), 3u);
  ASSERT_EQ(c64.size(), c32.size());
  EXPECT_EQ(c64[1], (std::array<int, 3>{0, 1, 0}));  // over the corner: y first
  EXPECT_EQ(c32[1], (std::array<int, 3>{1, 0, 0}));  // a tie: the lower axis first
  EXPECT_EQ(c64[2], c32[2]);
  // 1e-3 above the corner both see it: the walks agree.
  const Vec3 clear = normalize(Vec3{0.9, 0.901, 0});
  EXPECT_EQ(cells_of<double>(g, o, clear), cells_of<float>(g, o, clear));
}

TEST(DdaPrecision, Fp32WalksAgreeWithFp64AwayFromBoundaries) {
  // Random rays on random grids: a float walk visits the voxels of the double walk except where
  // a crossing lies within float rounding of another (then a zero-length voxel may differ).
  std::mt19937 rng(17);
  int same = 0, walks = 0;
  for (int i = 0; i < 500; ++i) {
    const std::array<int, 3> n{1 + int(rng() % 20), 1 + int(rng() % 20), 1 + int(rng() % 20)};
    const Grid g =
        make_grid({test::uniform(rng, -5, 5), test::uniform(rng, -5, 5), test::uniform(rng, -5, 5)},
                  {test::log_uniform(rng, -1, 1), test::log_uniform(rng, -1, 1),
                   test::log_uniform(rng, -1, 1)},
                  n);
    const Vec3 o = g.box.lo + Vec3(test::uniform(rng, -0.2, 1.2), test::uniform(rng, -0.2, 1.2),
                                   test::uniform(rng, -0.2, 1.2)) *
                                  g.box.extent();
    const Vec3 d = test::random_unit(rng);
    const auto c64 = cells_of<double>(g, o, d), c32 = cells_of<float>(g, o, d);
    ASSERT_LE(c32.size(), size_t(n[0] + n[1] + n[2]));
    ++walks;
    same += c64 == c32;
  }
  std::printf("[numerics] 3DDDA fp32 against fp64: %d of %d random walks visit the same voxels\n",
              same, walks);
  EXPECT_GE(same, walks * 95 / 100);
}

}  // namespace
}  // namespace rtm
