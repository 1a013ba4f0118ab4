// Quadric primitives: every constructor against the analytic implicit form of its shape.
//
// Each shape is sampled parametrically (independently of the constructor's matrix algebra);
// on-surface samples must give Q ≈ 0 relative to the size of Q's terms, points pushed off the
// surface along the analytic normal must have the right sign, ∇Q must be parallel to the
// analytic normal (and point to the Q > 0 side), every kept sample must lie inside `bounds`
// and the clips, and the clips must sit exactly at the caps.
#include "geom/quadric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>
#include "geom/test_random.h"

namespace rtm {
namespace {

using namespace rtm::test;

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// 10^U(lo, hi): spreads sizes over several decades.

Vec3 random_point(std::mt19937& rng, double scale) {
  return Vec3{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)} * scale;
}

/// A random right-handed orthonormal frame (not the one Frame::along would pick).
Frame random_frame(std::mt19937& rng, const Vec3& origin) {
  const Vec3 z = random_unit(rng);
  const Frame base = Frame::along(origin, z);
  const double a = uniform(rng, 0, 2 * kPi);
  Frame f;
  f.origin = origin;
  f.ez = base.ez;
  f.ex = normalize(std::cos(a) * base.ex + std::sin(a) * base.ey);
  f.ey = cross(f.ez, f.ex);
  return f;
}

/// A perpendicular pair for axis a, built independently of Frame::along.
void perpendicular_pair(const Vec3& a, Vec3& u, Vec3& v) {
  const Vec3 helper = std::abs(a.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
  u = normalize(helper - dot(helper, a) * a);
  v = cross(a, u);
}

/// Sum of the magnitudes of Q's ten terms at p: the scale of Q's rounding error at p.
double term_scale(const Quadric& q, const Vec3& p) {
  const auto& c = q.c;
  return std::abs(c[kA] * p.x * p.x) + std::abs(c[kB] * p.y * p.y) + std::abs(c[kC] * p.z * p.z) +
         std::abs(c[kD] * p.x * p.y) + std::abs(c[kE] * p.y * p.z) + std::abs(c[kF] * p.z * p.x) +
         std::abs(c[kG] * p.x) + std::abs(c[kH] * p.y) + std::abs(c[kI] * p.z) + std::abs(c[kJ]);
}

/// Coefficients A..J of any quadratic polynomial, extracted by evaluating it at a few points.
std::array<double, 10> coefficients_of(const std::function<double(const Vec3&)>& f) {
  std::array<double, 10> c{};
  const double f0 = f({0, 0, 0});
  const Vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i) {
    const double fp = f(e[i]), fm = f(-e[i]);
    c[kA + i] = (fp + fm) / 2 - f0;  // A, B, C
    c[kG + i] = (fp - fm) / 2;       // G, H, I
  }
  c[kJ] = f0;
  // f(ei + ej) = Aii + Ajj + cross + Gi + Gj + J.
  const int pairs[3][3] = {{0, 1, kD}, {1, 2, kE}, {2, 0, kF}};
  for (const auto& pr : pairs)
    c[pr[2]] =
        f(e[pr[0]] + e[pr[1]]) - c[kA + pr[0]] - c[kA + pr[1]] - c[kG + pr[0]] - c[kG + pr[1]] - f0;
  return c;
}

::testing::AssertionResult CoefficientsMatch(const Quadric& q,
                                             const std::array<double, 10>& expected,
                                             double rel = 1e-11) {
  double scale = 0;
  for (double x : expected) scale = std::max(scale, std::abs(x));
  for (int i = 0; i < 10; ++i)
    if (!(std::abs(q.c[i] - expected[i]) <= rel * scale))
      return ::testing::AssertionFailure() << "coefficient "
                                           << "ABCDEFGHIJ"[i] << " is " << q.c[i] << ", expected "
                                           << expected[i] << " (scale " << scale << ")";
  return ::testing::AssertionSuccess();
}

/// Everything that must hold at a point p of the kept surface.
/// n: analytic normal pointing to the Q > 0 side (any length); size: the shape's length scale.
/// interior: p is not on a clip boundary, so it must pass the exact (untolerated) clip test.
::testing::AssertionResult SurfacePoint(const Primitive& pr, const Vec3& p, const Vec3& n,
                                        double size, bool interior = true, bool check_sign = true) {
  const double scale = term_scale(pr.q, p);
  const double v = pr.q.value(p);
  if (!(std::abs(v) <= 1e-11 * scale))
    return ::testing::AssertionFailure() << "Q(p) = " << v << " relative " << v / scale
                                         << " at p = (" << p.x << ", " << p.y << ", " << p.z << ")";
  const Vec3 nh = normalize(n);
  if (check_sign) {
    const double delta = 1e-5 * size;
    if (!(pr.q.value(p + delta * nh) > 0))
      return ::testing::AssertionFailure() << "Q is not > 0 on the normal side";
    if (!(pr.q.value(p - delta * nh) < 0))
      return ::testing::AssertionFailure() << "Q is not < 0 on the other side";
  }
  const Vec3 g = pr.q.gradient(p);
  if (!(length(g) > 0)) return ::testing::AssertionFailure() << "zero gradient";
  const double cosang = dot(normalize(g), nh);
  if (!(cosang >= 1 - 1e-9))
    return ::testing::AssertionFailure()
           << "gradient not parallel to the analytic normal: cos = " << cosang;
  const double tol = 1e-12 * (max_abs(p) + size);
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= pr.bounds.lo[a] - tol && p[a] <= pr.bounds.hi[a] + tol))
      return ::testing::AssertionFailure()
             << "point outside bounds on axis " << a << ": " << p[a] << " not in ["
             << pr.bounds.lo[a] << ", " << pr.bounds.hi[a] << "]";
  for (size_t k = 0; k < pr.clips.size(); ++k) {
    const double e = pr.clips[k].eval(p);
    const double ctol = 1e-10 * (max_abs(p) + size) * length(pr.clips[k].n);
    if (!(e <= ctol))
      return ::testing::AssertionFailure() << "clip " << k << " rejects a kept point: " << e;
  }
  if (interior && !pr.inside_clips(p))
    return ::testing::AssertionFailure() << "inside_clips rejects an interior point";
  return ::testing::AssertionSuccess();
}

/// Index of the clip that vanishes at p (within tolerance), or -1.
int vanishing_clip(const Primitive& pr, const Vec3& p, double size) {
  for (size_t k = 0; k < pr.clips.size(); ++k)
    if (std::abs(pr.clips[k].eval(p)) <= 1e-10 * (max_abs(p) + size) * length(pr.clips[k].n))
      return int(k);
  return -1;
}

// ---------------------------------------------------------------------------------------------
// Sphere

TEST(QuadricSphere, CoefficientsAreTheImplicitForm) {
  std::mt19937 rng(1);
  for (int i = 0; i < 200; ++i) {
    const Vec3 c = random_point(rng, log_uniform(rng, -2, 3));
    const double r = log_uniform(rng, -2, 2);
    const Primitive p = make_sphere(c, r);
    EXPECT_EQ(p.kind, ShapeKind::Sphere);
    EXPECT_TRUE(p.clips.empty());
    EXPECT_TRUE(CoefficientsMatch(
        p.q, coefficients_of([&](const Vec3& x) { return dot(x - c, x - c) - r * r; })));
    EXPECT_EQ(p.p0, c);
    EXPECT_EQ(p.r0, r);
  }
}

TEST(QuadricSphere, SurfaceSamples) {
  std::mt19937 rng(2);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 c = random_point(rng, log_uniform(rng, -2, 3));
    const double r = log_uniform(rng, -2, 2);
    const Primitive p = make_sphere(c, r);
    const Vec3 u = random_unit(rng);
    ASSERT_TRUE(SurfacePoint(p, c + r * u, u, r)) << "case " << i;
  }
}

TEST(QuadricSphere, BoundsAreTheExactBox) {
  const Vec3 c{1.5, -2.25, 3};
  const Primitive p = make_sphere(c, 0.75);
  EXPECT_EQ(p.bounds.lo, c - Vec3(0.75));
  EXPECT_EQ(p.bounds.hi, c + Vec3(0.75));
  EXPECT_GT(p.q.value(c + Vec3(0.75)), 0);  // box corner is outside the sphere
  EXPECT_LT(p.q.value(c), 0);               // centre is inside
}

TEST(QuadricSphere, RejectsBadArguments) {
  const double inf = kInf;
  EXPECT_THROW(make_sphere({kNaN, 0, 0}, 1), std::invalid_argument);
  EXPECT_THROW(make_sphere({0, inf, 0}, 1), std::invalid_argument);
  EXPECT_THROW(make_sphere({0, 0, -inf}, 1), std::invalid_argument);
  EXPECT_THROW(make_sphere({0, 0, 0}, 0), std::invalid_argument);
  EXPECT_THROW(make_sphere({0, 0, 0}, -1), std::invalid_argument);
  EXPECT_THROW(make_sphere({0, 0, 0}, kNaN), std::invalid_argument);
  EXPECT_THROW(make_sphere({0, 0, 0}, inf), std::invalid_argument);
  EXPECT_NO_THROW(make_sphere({0, 0, 0}, 1e-9));
}

// ---------------------------------------------------------------------------------------------
// Ellipsoid

TEST(QuadricEllipsoid, RotatedFrameCoefficientsAndSamples) {
  std::mt19937 rng(3);
  for (int i = 0; i < 500; ++i) {
    const Frame f = random_frame(rng, random_point(rng, log_uniform(rng, -1, 2)));
    const Vec3 r{log_uniform(rng, -1, 1), log_uniform(rng, -1, 1), log_uniform(rng, -1, 1)};
    const Primitive p = make_ellipsoid(f, r);
    EXPECT_EQ(p.kind, ShapeKind::Ellipsoid);
    ASSERT_TRUE(CoefficientsMatch(p.q, coefficients_of([&](const Vec3& x) {
                                    const Vec3 d = x - f.origin;
                                    const double a = dot(d, f.ex) / r.x, b = dot(d, f.ey) / r.y,
                                                 c = dot(d, f.ez) / r.z;
                                    return a * a + b * b + c * c - 1;
                                  })))
        << "case " << i;
    const double size = std::min({r.x, r.y, r.z});
    for (int k = 0; k < 8; ++k) {
      const double th = uniform(rng, 0, 2 * kPi), ph = uniform(rng, 0.01, kPi - 0.01);
      const Vec3 local{r.x * std::sin(ph) * std::cos(th), r.y * std::sin(ph) * std::sin(th),
                       r.z * std::cos(ph)};
      // Normal from the parametric tangents, not from the implicit form.
      const Vec3 dth{-r.x * std::sin(ph) * std::sin(th), r.y * std::sin(ph) * std::cos(th), 0};
      const Vec3 dph{r.x * std::cos(ph) * std::cos(th), r.y * std::cos(ph) * std::sin(th),
                     -r.z * std::sin(ph)};
      Vec3 nl = cross(dph, dth);
      if (dot(nl, local) < 0) nl = -nl;
      const Vec3 pw = f.origin + local.x * f.ex + local.y * f.ey + local.z * f.ez;
      const Vec3 nw = nl.x * f.ex + nl.y * f.ey + nl.z * f.ez;
      ASSERT_TRUE(SurfacePoint(p, pw, nw, size)) << "case " << i << " sample " << k;
    }
    // The box is exact: on each axis the extreme point is on the surface and on the box face.
    const Vec3 e[3] = {f.ex, f.ey, f.ez};
    for (int a = 0; a < 3; ++a) {
      const Vec3 row{e[0][a] * r.x, e[1][a] * r.y, e[2][a] * r.z};
      const Vec3 u = row / length(row);
      const Vec3 local{r.x * u.x, r.y * u.y, r.z * u.z};
      const Vec3 top = f.origin + local.x * e[0] + local.y * e[1] + local.z * e[2];
      EXPECT_LE(std::abs(p.q.value(top)), 1e-11 * term_scale(p.q, top));
      EXPECT_NEAR(p.bounds.hi[a], top[a], 1e-12 * (max_abs(top) + size));
      EXPECT_NEAR(p.bounds.lo[a], 2 * f.origin[a] - top[a], 1e-12 * (max_abs(top) + size));
    }
  }
}

TEST(QuadricEllipsoid, AxisAlignedIsTheTextbookForm) {
  Frame f;
  f.origin = {1, 2, 3};
  const Primitive p = make_ellipsoid(f, {2, 4, 0.5});
  EXPECT_TRUE(
      CoefficientsMatch(p.q, {0.25, 1.0 / 16, 4, 0, 0, 0, -0.5, -0.25, -24, 0.25 + 0.25 + 36 - 1}));
  EXPECT_EQ(p.bounds.lo, Vec3(-1, -2, 2.5));
  EXPECT_EQ(p.bounds.hi, Vec3(3, 6, 3.5));
}

TEST(QuadricEllipsoid, RejectsBadArguments) {
  const Frame f;
  EXPECT_THROW(make_ellipsoid(f, {0, 1, 1}), std::invalid_argument);
  EXPECT_THROW(make_ellipsoid(f, {1, -1, 1}), std::invalid_argument);
  EXPECT_THROW(make_ellipsoid(f, {1, 1, kNaN}), std::invalid_argument);
  EXPECT_THROW(make_ellipsoid(f, {1, kInf, 1}), std::invalid_argument);
  Frame bad = f;
  bad.origin.x = kNaN;
  EXPECT_THROW(make_ellipsoid(bad, {1, 1, 1}), std::invalid_argument);
  bad = f;
  bad.ex = {2, 0, 0};  // not unit
  EXPECT_THROW(make_ellipsoid(bad, {1, 1, 1}), std::invalid_argument);
  bad = f;
  bad.ey = normalize(Vec3{1, 1, 0});  // not orthogonal
  EXPECT_THROW(make_ellipsoid(bad, {1, 1, 1}), std::invalid_argument);
  bad = f;
  bad.ez = {0, 0, kInf};
  EXPECT_THROW(make_ellipsoid(bad, {1, 1, 1}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Surfaces of revolution: cones and cylinders, paraboloids, hyperboloids.

/// A meridian (r(u), z(u)) of a surface of revolution about axis `a` through `o`, with
/// derivatives. sign orients z_u w − r_u a towards Q > 0.
struct Meridian {
  std::function<void(double u, double& r, double& z, double& ru, double& zu)> at;
  double u0, u1;
  double sign = 1;
  /// Parameter range of the whole kept surface, for the box check, if wider than [u0, u1].
  double box_u0 = kNaN, box_u1 = kNaN;
};

/// Samples the meridians all round, checks every sample, and checks the box is tight: it holds
/// every sample and exceeds the sampled extremes by at most `slack_rel` of the shape's size.
void check_revolution(const Primitive& p, const Vec3& o, const Vec3& a, const Vec3& u,
                      const Vec3& v, const std::vector<Meridian>& meridians, double size,
                      std::mt19937& rng, const char* what) {
  SCOPED_TRACE(what);
  for (const Meridian& m : meridians) {
    for (int k = 0; k < 12; ++k) {
      const double s = uniform(rng, m.u0, m.u1), th = uniform(rng, 0, 2 * kPi);
      double r, z, ru, zu;
      m.at(s, r, z, ru, zu);
      const Vec3 w = std::cos(th) * u + std::sin(th) * v;
      const Vec3 pt = o + z * a + r * w;
      const Vec3 n = m.sign * (zu * w - ru * a);
      // Near the axis a step along the normal can cross the surface again: no sign check there.
      ASSERT_TRUE(SurfacePoint(p, pt, n, size, true, r > 1e-3 * size))
          << "u = " << s << " theta = " << th;
    }
  }
  // Box tightness: on each axis the extreme over a circle is o_i + z a_i ± r sqrt(1 − a_i²);
  // maximise over a dense set of meridian parameters.
  Vec3 lo(kInf), hi(-kInf);
  for (const Meridian& m : meridians)
    for (int k = 0; k <= 1500; ++k) {
      const double b0 = std::isnan(m.box_u0) ? m.u0 : m.box_u0,
                   b1 = std::isnan(m.box_u1) ? m.u1 : m.box_u1;
      double r, z, ru, zu;
      m.at(b0 + (b1 - b0) * k / 1500.0, r, z, ru, zu);
      for (int i = 0; i < 3; ++i) {
        const double c = o[i] + z * a[i],
                     h = std::abs(r) * std::sqrt(std::max(0.0, 1 - a[i] * a[i]));
        lo[i] = std::min(lo[i], c - h);
        hi[i] = std::max(hi[i], c + h);
      }
    }
  const double tol = 1e-12 * (max_abs(o) + size);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LE(p.bounds.lo[i], lo[i] + tol) << "box does not hold the surface, axis " << i;
    EXPECT_GE(p.bounds.hi[i], hi[i] - tol) << "box does not hold the surface, axis " << i;
    EXPECT_GE(p.bounds.lo[i], lo[i] - 1e-3 * size) << "box is loose, axis " << i;
    EXPECT_LE(p.bounds.hi[i], hi[i] + 1e-3 * size) << "box is loose, axis " << i;
  }
}

/// The cap clips of a shape whose kept part is z0 <= a·(p − o) <= z1: there are exactly two,
/// one vanishing on each cap plane, and points just past either cap are rejected.
void check_caps(const Primitive& p, const Vec3& o, const Vec3& a, const Vec3& u, const Vec3& v,
                double z0, double z1, double size, std::mt19937& rng) {
  int at0 = -1, at1 = -1;
  for (int k = 0; k < 20; ++k) {
    const double along_v = uniform(rng, -2, 2);  // before along u (test_random.h says why)
    const Vec3 off = uniform(rng, -2, 2) * size * u + along_v * size * v;
    const Vec3 c0 = o + z0 * a + off, c1 = o + z1 * a + off;
    const int k0 = vanishing_clip(p, c0, size), k1 = vanishing_clip(p, c1, size);
    ASSERT_GE(k0, 0) << "no clip vanishes on the z0 cap plane";
    ASSERT_GE(k1, 0) << "no clip vanishes on the z1 cap plane";
    ASSERT_NE(k0, k1);
    if (at0 < 0) at0 = k0, at1 = k1;
    EXPECT_EQ(k0, at0);
    EXPECT_EQ(k1, at1);
    const double eps = 1e-6 * (z1 - z0);
    EXPECT_FALSE(p.inside_clips(o + (z0 - eps) * a + off * 0.0)) << "point before the z0 cap kept";
    EXPECT_FALSE(p.inside_clips(o + (z1 + eps) * a + off * 0.0)) << "point past the z1 cap kept";
    EXPECT_TRUE(p.inside_clips(o + (z0 + eps) * a)) << "point just inside the z0 cap rejected";
    EXPECT_TRUE(p.inside_clips(o + (z1 - eps) * a)) << "point just inside the z1 cap rejected";
  }
  // Cap normals are the axis (outwards).
  EXPECT_GE(dot(normalize(p.clips[size_t(at0)].n), -a), 1 - 1e-12);
  EXPECT_GE(dot(normalize(p.clips[size_t(at1)].n), a), 1 - 1e-12);
}

std::vector<Vec3> test_axes(std::mt19937& rng) {
  std::vector<Vec3> axes = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},  {0, -1, 0},
                            {0, 0, 1},  {0, 0, -1}, {1, 1, 1},  {-1, -1, -1},
                            {1, -1, 0}, {0, 1, 1},  {1, 0, -1}, {0.6, 0.6, 0.53}};
  for (int i = 0; i < 60; ++i) {
    const double size = log_uniform(rng, -1, 1);  // before the direction (test_random.h says why)
    axes.push_back(random_unit(rng) * size);
  }
  return axes;
}

TEST(QuadricCone, CylindersAndConesOnArbitraryAxes) {
  std::mt19937 rng(4);
  const std::vector<Vec3> axes = test_axes(rng);
  int count = 0;
  for (const Vec3& axis_in : axes)
    for (int variant = 0; variant < 6; ++variant, ++count) {
      SCOPED_TRACE(::testing::Message() << "axis (" << axis_in.x << ", " << axis_in.y << ", "
                                        << axis_in.z << ") variant " << variant);
      const Vec3 base = random_point(rng, log_uniform(rng, -1, 2));
      const double h = log_uniform(rng, -1, 1);
      const Vec3 apex = base + h * normalize(axis_in);
      const double a_len = length(apex - base);
      const Vec3 a = (apex - base) / a_len;
      double r0 = log_uniform(rng, -1, 0.5), r1 = log_uniform(rng, -1, 0.5);
      switch (variant) {
        case 0:
          r1 = r0;
          break;  // cylinder
        case 1:
          r1 = 0;
          break;  // pointed cone
        case 2:
          r0 = 0;
          break;  // pointed at the base
        default:
          break;  // truncated cone
      }
      const Primitive p = make_cone(base, r0, apex, r1);
      EXPECT_EQ(p.kind, r0 == r1 ? ShapeKind::Cylinder : ShapeKind::Cone);
      const double k = (r1 - r0) / a_len;
      ASSERT_TRUE(CoefficientsMatch(p.q, coefficients_of([&](const Vec3& x) {
                                      const Vec3 d = x - base;
                                      const double z = dot(d, a), r = r0 + k * z;
                                      return dot(d, d) - z * z - r * r;
                                    })));
      Vec3 u, v;
      perpendicular_pair(a, u, v);
      const double size = std::max(r0, r1);
      Meridian m;
      m.at = [&](double s, double& r, double& z, double& ru, double& zu) {
        z = s * a_len;
        r = r0 + k * z;
        ru = k;
        zu = 1;
      };
      // Stay off a pointed apex, where the gradient vanishes.
      m.u0 = r0 == 0 ? 1e-3 : 0;
      m.u1 = r1 == 0 ? 1 - 1e-3 : 1;
      m.box_u0 = 0;
      m.box_u1 = 1;
      check_revolution(p, base, a, u, v, {m}, size, rng, "cone");
      check_caps(p, base, a, u, v, 0, a_len, size, rng);
      ASSERT_EQ(p.clips.size(), 2u);
      // The rims lie on the caps and are kept (within tolerance).
      for (double s : {0.0, 1.0}) {
        const double r = r0 + (r1 - r0) * s;
        const Vec3 rim = base + s * (apex - base) + r * u;
        EXPECT_LE(std::abs(p.q.value(rim)), 1e-11 * term_scale(p.q, rim));
        EXPECT_GE(vanishing_clip(p, rim, size), 0);
      }
      // The quadric continues past the caps; those points are on Q = 0 but clipped away.
      for (double s : {-0.05, 1.05}) {
        const double r = r0 + (r1 - r0) * s;
        const Vec3 beyond = base + s * (apex - base) + r * v;
        EXPECT_LE(std::abs(p.q.value(beyond)), 1e-11 * term_scale(p.q, beyond));
        EXPECT_FALSE(p.inside_clips(beyond));
      }
      EXPECT_EQ(p.p0, base);
      EXPECT_EQ(p.p1, apex);
    }
  EXPECT_GT(count, 400);
}

TEST(QuadricCone, AxisAlignedCylinderIsTheTextbookForm) {
  const Primitive p = make_cone({1, 2, -1}, 3, {1, 2, 4}, 3);
  EXPECT_EQ(p.kind, ShapeKind::Cylinder);
  EXPECT_TRUE(CoefficientsMatch(p.q, {1, 1, 0, 0, 0, 0, -2, -4, 0, 1 + 4 - 9}));
  EXPECT_EQ(p.bounds.lo, Vec3(-2, -1, -1));
  EXPECT_EQ(p.bounds.hi, Vec3(4, 5, 4));
}

TEST(QuadricCone, DiagonalCylinderHasCrossTerms) {
  // Axis (1,1,1)/√3 through the origin, radius 1: Q = |p|² − (p·a)² − 1.
  const Primitive p = make_cone({0, 0, 0}, 1, {2, 2, 2}, 1);
  const double t = 2.0 / 3;
  EXPECT_TRUE(CoefficientsMatch(p.q, {t, t, t, -t, -t, -t, 0, 0, 0, -1}));
}

TEST(QuadricCone, NegativeRadiiGiveTheSameSurface) {
  // NFF: negative radii mean "only the inside is visible"; the surface is unchanged.
  const Primitive pos = make_cone({0, 1, 2}, 1.5, {3, -1, 2}, 0.5);
  const Primitive neg = make_cone({0, 1, 2}, -1.5, {3, -1, 2}, -0.5);
  EXPECT_EQ(pos.q.c, neg.q.c);
  EXPECT_EQ(neg.r0, 1.5);
  EXPECT_EQ(neg.r1, 0.5);
}

TEST(QuadricCone, RejectsBadArguments) {
  EXPECT_THROW(make_cone({0, 0, 0}, 1, {0, 0, 0}, 1), std::invalid_argument);  // coincident ends
  EXPECT_THROW(make_cone({1, 2, 3}, 1, {1, 2, 3}, 0.5), std::invalid_argument);
  EXPECT_THROW(make_cone({0, 0, 0}, 0, {0, 0, 1}, 0), std::invalid_argument);  // both radii zero
  EXPECT_THROW(make_cone({kNaN, 0, 0}, 1, {0, 0, 1}, 1), std::invalid_argument);
  EXPECT_THROW(make_cone({0, 0, 0}, 1, {0, kInf, 1}, 1), std::invalid_argument);
  EXPECT_THROW(make_cone({0, 0, 0}, kNaN, {0, 0, 1}, 1), std::invalid_argument);
  EXPECT_THROW(make_cone({0, 0, 0}, 1, {0, 0, 1}, kInf), std::invalid_argument);
  EXPECT_NO_THROW(make_cone({0, 0, 0}, 1, {0, 0, 1}, 0));
  EXPECT_NO_THROW(make_cone({0, 0, 0}, 0, {0, 0, 1}, 1));
}

TEST(QuadricParaboloid, FramesSamplesAndBox) {
  std::mt19937 rng(5);
  for (int i = 0; i < 400; ++i) {
    const Frame f = random_frame(rng, random_point(rng, log_uniform(rng, -1, 2)));
    const double k = log_uniform(rng, -1, 1), height = log_uniform(rng, -1, 1);
    const Primitive p = make_paraboloid(f, k, height);
    EXPECT_EQ(p.kind, ShapeKind::Paraboloid);
    ASSERT_TRUE(CoefficientsMatch(p.q, coefficients_of([&](const Vec3& x) {
                                    const Vec3 d = x - f.origin;
                                    const double a = dot(d, f.ex), b = dot(d, f.ey),
                                                 c = dot(d, f.ez);
                                    return a * a + b * b - k * c;
                                  })))
        << "case " << i;
    const double rmax = std::sqrt(k * height), size = std::max(rmax, height);
    Meridian m;  // parameter r: z = r² / k
    m.at = [&](double s, double& r, double& z, double& ru, double& zu) {
      r = s;
      z = s * s / k;
      ru = 1;
      zu = 2 * s / k;
    };
    m.u0 = 0;
    m.u1 = rmax;
    // Normal (2r/k) w − a: at the vertex −a, towards Q > 0 (below the bowl).
    check_revolution(p, f.origin, f.ez, f.ex, f.ey, {m}, size, rng, "paraboloid");
    check_caps(p, f.origin, f.ez, f.ex, f.ey, 0, height, size, rng);
    ASSERT_EQ(p.clips.size(), 2u);
  }
}

TEST(QuadricParaboloid, TiltedShallowBowlStaysInItsBox) {
  // A wide, shallow bowl tilted so its rim dips below its widest part along world x: the box
  // of the vertex and the rim disc alone does not hold it.
  const Frame f = Frame::along({0, 0, 0}, {-0.7, 0, 0.714142842854285});
  const Primitive p = make_paraboloid(f, 1, 1);
  const Vec3 a = f.ez;
  const double sx = std::sqrt(1 - a.x * a.x);
  double best = -kInf;
  for (int i = 0; i <= 1000; ++i) {
    const double z = i / 1000.0;
    best =
        std::max(best, z * a.x + std::sqrt(z) * sx);  // farthest world x of the circle at height z
  }
  EXPECT_GE(p.bounds.hi.x, best - 1e-12);
}

TEST(QuadricParaboloid, RejectsBadArguments) {
  const Frame f;
  EXPECT_THROW(make_paraboloid(f, 0, 1), std::invalid_argument);
  EXPECT_THROW(make_paraboloid(f, -1, 1), std::invalid_argument);
  EXPECT_THROW(make_paraboloid(f, 1, 0), std::invalid_argument);
  EXPECT_THROW(make_paraboloid(f, 1, -2), std::invalid_argument);
  EXPECT_THROW(make_paraboloid(f, kNaN, 1), std::invalid_argument);
  EXPECT_THROW(make_paraboloid(f, 1, kInf), std::invalid_argument);
  Frame bad = f;
  bad.ez = {0, 0, 0.5};
  EXPECT_THROW(make_paraboloid(bad, 1, 1), std::invalid_argument);
}

TEST(QuadricHyperboloid, OneSheet) {
  std::mt19937 rng(6);
  for (int i = 0; i < 400; ++i) {
    const Frame f = random_frame(rng, random_point(rng, log_uniform(rng, -1, 2)));
    const double a = log_uniform(rng, -1, 0.5), c = log_uniform(rng, -1, 0.5),
                 hh = log_uniform(rng, -1, 0.5);
    const Primitive p = make_hyperboloid1(f, a, c, hh);
    EXPECT_EQ(p.kind, ShapeKind::Hyperboloid1);
    ASSERT_TRUE(CoefficientsMatch(p.q, coefficients_of([&](const Vec3& x) {
                                    const Vec3 d = x - f.origin;
                                    const double lx = dot(d, f.ex) / a, ly = dot(d, f.ey) / a,
                                                 lz = dot(d, f.ez) / c;
                                    return lx * lx + ly * ly - lz * lz - 1;
                                  })))
        << "case " << i;
    Meridian m;  // z = c sinh u, r = a cosh u
    m.at = [&](double s, double& r, double& z, double& ru, double& zu) {
      r = a * std::cosh(s);
      z = c * std::sinh(s);
      ru = a * std::sinh(s);
      zu = c * std::cosh(s);
    };
    m.u1 = std::asinh(hh / c);
    m.u0 = -m.u1;
    const double size = std::max(a, hh);
    check_revolution(p, f.origin, f.ez, f.ex, f.ey, {m}, size, rng, "hyperboloid1");
    check_caps(p, f.origin, f.ez, f.ex, f.ey, -hh, hh, size, rng);
    ASSERT_EQ(p.clips.size(), 2u);
  }
}

TEST(QuadricHyperboloid, TwoSheets) {
  std::mt19937 rng(7);
  for (int i = 0; i < 400; ++i) {
    const Frame f = random_frame(rng, random_point(rng, log_uniform(rng, -1, 2)));
    const double a = log_uniform(rng, -1, 0.5), c = log_uniform(rng, -1, 0.5);
    const double hh = c * (1 + log_uniform(rng, -2, 0.5));
    const Primitive p = make_hyperboloid2(f, a, c, hh);
    EXPECT_EQ(p.kind, ShapeKind::Hyperboloid2);
    ASSERT_TRUE(CoefficientsMatch(p.q, coefficients_of([&](const Vec3& x) {
                                    const Vec3 d = x - f.origin;
                                    const double lx = dot(d, f.ex) / a, ly = dot(d, f.ey) / a,
                                                 lz = dot(d, f.ez) / c;
                                    return lx * lx + ly * ly - lz * lz + 1;
                                  })))
        << "case " << i;
    // Upper sheet z = c cosh u, lower z = −c cosh u; r = a sinh u. Q > 0 between the sheets.
    Meridian up, down;
    up.at = [&](double s, double& r, double& z, double& ru, double& zu) {
      r = a * std::sinh(s);
      z = c * std::cosh(s);
      ru = a * std::cosh(s);
      zu = c * std::sinh(s);
    };
    down.at = [&](double s, double& r, double& z, double& ru, double& zu) {
      r = a * std::sinh(s);
      z = -c * std::cosh(s);
      ru = a * std::cosh(s);
      zu = -c * std::sinh(s);
    };
    up.u0 = down.u0 = 0;
    up.u1 = down.u1 = std::acosh(hh / c);
    down.sign = -1;
    const double size = std::max({a, c, hh - c});
    check_revolution(p, f.origin, f.ez, f.ex, f.ey, {up, down}, size, rng, "hyperboloid2");
    check_caps(p, f.origin, f.ez, f.ex, f.ey, -hh, hh, size, rng);
    // The gap between the sheets holds no surface: Q > 0 on the axis for |z| < c.
    EXPECT_GT(p.q.value(f.origin), 0);
    EXPECT_GT(p.q.value(f.origin + 0.99 * c * f.ez), 0);
    EXPECT_LT(p.q.value(f.origin - 1.01 * c * f.ez), 0);
  }
}

TEST(QuadricHyperboloid, RejectsBadArguments) {
  const Frame f;
  EXPECT_THROW(make_hyperboloid1(f, 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_hyperboloid1(f, 1, -1, 1), std::invalid_argument);
  EXPECT_THROW(make_hyperboloid1(f, 1, 1, 0), std::invalid_argument);
  EXPECT_THROW(make_hyperboloid1(f, kNaN, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_hyperboloid2(f, 1, 1, 1), std::invalid_argument);  // half height must exceed c
  EXPECT_THROW(make_hyperboloid2(f, 1, 2, 1.5), std::invalid_argument);
  EXPECT_THROW(make_hyperboloid2(f, 1, 1, kInf), std::invalid_argument);
  EXPECT_THROW(make_hyperboloid2(f, -1, 1, 2), std::invalid_argument);
  EXPECT_THROW(make_hyperboloid2(f, 1, 0, 2), std::invalid_argument);
  Frame bad = f;
  bad.origin.z = kInf;
  EXPECT_THROW(make_hyperboloid1(bad, 1, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_hyperboloid2(bad, 1, 1, 2), std::invalid_argument);
  EXPECT_NO_THROW(make_hyperboloid2(f, 1, 1, 1.001));
}

// ---------------------------------------------------------------------------------------------
// Plane

TEST(QuadricPlane, NormalisedImplicitFormClippedToTheBox) {
  std::mt19937 rng(8);
  for (int i = 0; i < 500; ++i) {
    const double size = log_uniform(rng, -3, 3);  // before the direction (test_random.h says why)
    const Vec3 n = random_unit(rng) * size;
    const Vec3 nh = normalize(n);
    const double ext = log_uniform(rng, -1, 1);
    const Vec3 centre = random_point(rng, log_uniform(rng, -1, 2));
    const double d = -dot(n, centre);  // the plane passes through centre
    const Aabb box{centre - Vec3(ext, 2 * ext, 0.5 * ext), centre + Vec3(ext, 2 * ext, 0.5 * ext)};
    const Primitive p = make_plane(n, d, box);
    EXPECT_EQ(p.kind, ShapeKind::Plane);
    ASSERT_TRUE(CoefficientsMatch(
        p.q, coefficients_of([&](const Vec3& x) { return dot(nh, x) + d / length(n); })));
    EXPECT_EQ(p.bounds.lo, box.lo);
    EXPECT_EQ(p.bounds.hi, box.hi);
    ASSERT_EQ(p.clips.size(), 6u);
    Vec3 u, v;
    perpendicular_pair(nh, u, v);
    for (int k = 0; k < 10; ++k) {
      const double along_v = uniform(rng, -0.49, 0.49);  // before along u (test_random.h says why)
      const Vec3 q = centre + uniform(rng, -0.49, 0.49) * ext * u + along_v * ext * v;
      ASSERT_TRUE(SurfacePoint(p, q, nh, ext)) << "case " << i;
      // Far out in the plane, beyond the box: on the surface but clipped.
      const Vec3 far = centre + 5 * ext * (uniform(rng, 0, 1) < 0.5 ? u : v);
      EXPECT_LE(std::abs(p.q.value(far)), 1e-11 * term_scale(p.q, far));
      EXPECT_FALSE(p.inside_clips(far));
    }
    // Box faces are exactly where the clips vanish.
    for (int a = 0; a < 3; ++a) {
      Vec3 on_lo = centre, on_hi = centre;
      on_lo[a] = box.lo[a];
      on_hi[a] = box.hi[a];
      EXPECT_GE(vanishing_clip(p, on_lo, ext), 0);
      EXPECT_GE(vanishing_clip(p, on_hi, ext), 0);
      EXPECT_TRUE(p.inside_clips(on_lo));
      EXPECT_TRUE(p.inside_clips(on_hi));
    }
  }
}

TEST(QuadricPlane, FlatBoxIsAccepted) {
  const Primitive p = make_plane({0, 0, 1}, 0, Aabb{{-1, -1, 0}, {1, 1, 0}});
  EXPECT_TRUE(CoefficientsMatch(p.q, {0, 0, 0, 0, 0, 0, 0, 0, 1, 0}));
  EXPECT_TRUE(p.inside_clips({0.5, 0.5, 0}));
}

TEST(QuadricPlane, ExtremeNormalMagnitudesAreNormalised) {
  // Only the direction of n matters: neither a tiny nor a huge normal may under/overflow away.
  const Aabb box{{-1, -1, -1}, {1, 1, 1}};
  for (double s : {1e-200, 1e-160, 1e160, 1e200}) {
    SCOPED_TRACE(s);
    Primitive p;
    ASSERT_NO_THROW(p = make_plane(Vec3{0, 3, 4} * s, 5 * s, box));
    EXPECT_TRUE(CoefficientsMatch(p.q, {0, 0, 0, 0, 0, 0, 0, 0.6, 0.8, 1}));
  }
}

TEST(QuadricPlane, RejectsBadArguments) {
  const Aabb box{{-1, -1, -1}, {1, 1, 1}};
  EXPECT_THROW(make_plane({0, 0, 0}, 1, box), std::invalid_argument);
  EXPECT_THROW(make_plane({kNaN, 0, 1}, 1, box), std::invalid_argument);
  EXPECT_THROW(make_plane({0, kInf, 1}, 1, box), std::invalid_argument);
  EXPECT_THROW(make_plane({0, 0, 1}, kNaN, box), std::invalid_argument);
  EXPECT_THROW(make_plane({0, 0, 1}, kInf, box), std::invalid_argument);
  EXPECT_THROW(make_plane({0, 0, 1}, 0, Aabb{}), std::invalid_argument);  // default box is empty
  EXPECT_THROW(make_plane({0, 0, 1}, 0, Aabb{{0, 0, 0}, {1, -1, 1}}), std::invalid_argument);
  EXPECT_THROW(make_plane({0, 0, 1}, 0, Aabb{{0, 0, kNaN}, {1, 1, 1}}), std::invalid_argument);
  EXPECT_THROW(make_plane({0, 0, 1}, 0, Aabb{{0, 0, 0}, {1, kInf, 1}}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Polygon

std::vector<Vec3> regular_polygon(const Frame& f, int k, double radius, std::mt19937& rng) {
  // Jittered angles keep it convex (each step stays well below π).
  std::vector<Vec3> v;
  const double step = 2 * kPi / k, phase = uniform(rng, 0, 2 * kPi);
  for (int i = 0; i < k; ++i) {
    const double ang = phase + step * (i + uniform(rng, -0.3, 0.3));
    v.push_back(f.origin + radius * (std::cos(ang) * f.ex + std::sin(ang) * f.ey));
  }
  return v;
}

TEST(QuadricPolygon, TrianglesQuadsPentagons) {
  std::mt19937 rng(9);
  for (int k : {3, 4, 5})
    for (int i = 0; i < 300; ++i) {
      SCOPED_TRACE(::testing::Message() << k << "-gon case " << i);
      const Frame f = random_frame(rng, random_point(rng, log_uniform(rng, -1, 2)));
      const double radius = log_uniform(rng, -1, 1);
      const std::vector<Vec3> v = regular_polygon(f, k, radius, rng);
      const Primitive p = make_polygon(v);
      EXPECT_EQ(p.kind, ShapeKind::Polygon);
      // Counter-clockwise seen from +ez: the front normal is +ez.
      const double d = -dot(f.ez, f.origin);
      ASSERT_TRUE(
          CoefficientsMatch(p.q, coefficients_of([&](const Vec3& x) { return dot(f.ez, x) + d; })));
      ASSERT_EQ(p.clips.size(), size_t(k));
      EXPECT_EQ(p.vertices, v);
      // The box is the vertices' box.
      Aabb box;
      for (const Vec3& x : v) box.extend(x);
      EXPECT_EQ(p.bounds.lo, box.lo);
      EXPECT_EQ(p.bounds.hi, box.hi);
      // Interior points: random convex combinations, kept away from the edges.
      for (int s = 0; s < 10; ++s) {
        std::vector<double> w(static_cast<size_t>(k));
        double sum = 0;
        for (double& x : w) sum += (x = uniform(rng, 0.2, 1));
        Vec3 q{0, 0, 0};
        for (int j = 0; j < k; ++j) q += (w[size_t(j)] / sum) * v[size_t(j)];
        ASSERT_TRUE(SurfacePoint(p, q, f.ez, radius));
      }
      // Vertices and edge midpoints are on the boundary: some clip vanishes there, none rejects.
      for (int j = 0; j < k; ++j) {
        const Vec3& a = v[size_t(j)];
        const Vec3& b = v[size_t((j + 1) % k)];
        ASSERT_TRUE(SurfacePoint(p, a, f.ez, radius, false));
        ASSERT_TRUE(SurfacePoint(p, (a + b) / 2.0, f.ez, radius, false));
        EXPECT_GE(vanishing_clip(p, a, radius), 0);
        EXPECT_GE(vanishing_clip(p, (a + b) / 2.0, radius), 0);
        // Just outside the edge, in the plane: clipped.
        const Vec3 out = normalize(cross(b - a, f.ez));
        EXPECT_FALSE(p.inside_clips((a + b) / 2.0 + 1e-6 * radius * out));
        EXPECT_TRUE(p.inside_clips((a + b) / 2.0 - 1e-6 * radius * out));
      }
      // Clockwise order: the same polygon facing the other way.
      const std::vector<Vec3> rev(v.rbegin(), v.rend());
      const Primitive back = make_polygon(rev);
      for (int j = 0; j < 10; ++j)
        EXPECT_NEAR(back.q.c[size_t(j)], -p.q.c[size_t(j)], 1e-12 * (1 + max_abs(f.origin)));
      const Vec3 centroid = std::accumulate(v.begin(), v.end(), Vec3{0, 0, 0}) / double(k);
      EXPECT_TRUE(back.inside_clips(centroid));
    }
}

TEST(QuadricPolygon, DuplicateAndCollinearVertices) {
  const std::vector<Vec3> sq = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  // Repeated consecutive vertices and a closing copy of the first are dropped.
  const Primitive p =
      make_polygon({{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}});
  EXPECT_EQ(p.vertices, sq);
  EXPECT_EQ(p.clips.size(), 4u);
  // A vertex in the middle of an edge is harmless.
  const Primitive q = make_polygon({{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  EXPECT_TRUE(q.inside_clips({0.5, 0.5, 0}));
  EXPECT_TRUE(q.inside_clips({0.5, 0, 0}));
  EXPECT_FALSE(q.inside_clips({0.5, -1e-9, 0}));
  EXPECT_TRUE(CoefficientsMatch(q.q, {0, 0, 0, 0, 0, 0, 0, 0, 1, 0}));
}

TEST(QuadricPolygon, RejectsBadPolygons) {
  // Concave: a square with a notch.
  EXPECT_THROW(make_polygon({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {1, 1, 0}, {0, 2, 0}}),
               std::invalid_argument);
  // Non-planar: one corner of a square lifted.
  EXPECT_THROW(make_polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}}), std::invalid_argument);
  // Zero area: collinear, or all one point.
  EXPECT_THROW(make_polygon({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}), std::invalid_argument);
  EXPECT_THROW(make_polygon({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}), std::invalid_argument);
  EXPECT_THROW(make_polygon({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}), std::invalid_argument);
  // Self-intersecting: a bow tie and a pentagram.
  EXPECT_THROW(make_polygon({{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}), std::invalid_argument);
  {
    std::vector<Vec3> star;
    for (int i = 0; i < 5; ++i) {
      const double a = 2 * kPi * (2 * i % 5) / 5;
      star.push_back({std::cos(a), std::sin(a), 0});
    }
    EXPECT_THROW(make_polygon(star), std::invalid_argument);
  }
  // Too few vertices, before or after dropping repeats.
  EXPECT_THROW(make_polygon({{0, 0, 0}, {1, 0, 0}}), std::invalid_argument);
  EXPECT_THROW(make_polygon({{0, 0, 0}, {1, 0, 0}, {0, 0, 0}}), std::invalid_argument);
  EXPECT_THROW(make_polygon({}), std::invalid_argument);
  // Non-finite vertices.
  EXPECT_THROW(make_polygon({{0, 0, 0}, {1, 0, kNaN}, {0, 1, 0}}), std::invalid_argument);
  EXPECT_THROW(make_polygon({{0, 0, 0}, {1, 0, 0}, {0, kInf, 0}}), std::invalid_argument);
  // Planar to rounding: accepted.
  EXPECT_NO_THROW(make_polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 1e-12}, {0, 1, 0}}));
}

// ---------------------------------------------------------------------------------------------
// Raw quadrics and validate()

TEST(QuadricRaw, KeepsCoefficientsBoxAndClips) {
  std::mt19937 rng(10);
  for (int i = 0; i < 200; ++i) {
    std::array<double, 10> c;
    for (double& x : c) x = uniform(rng, -3, 3);
    const Vec3 lo = random_point(rng, 5);
    const Aabb box{lo, lo + uniform_zyx(rng, 0.1, 3)};
    const HalfSpace extra{random_unit(rng), uniform(rng, -1, 1)};
    const Primitive p = make_raw_quadric(c, box, {extra});
    EXPECT_EQ(p.kind, ShapeKind::Raw);
    EXPECT_EQ(p.q.c, c);
    EXPECT_EQ(p.bounds.lo, box.lo);
    EXPECT_EQ(p.bounds.hi, box.hi);
    ASSERT_EQ(p.clips.size(), 7u);
    EXPECT_EQ(p.clips.back().n, extra.n);
    EXPECT_EQ(p.clips.back().d, extra.d);
    // Box clips keep exactly the box.
    const Vec3 mid = (box.lo + box.hi) / 2.0;
    for (int a = 0; a < 3; ++a) {
      Vec3 out = mid;
      out[a] = box.hi[a] + 1e-9;
      EXPECT_FALSE(p.inside_clips(out));
      out[a] = box.lo[a] - 1e-9;
      EXPECT_FALSE(p.inside_clips(out));
    }
    // The value is the polynomial with those coefficients.
    const Vec3 x = random_point(rng, 3);
    const double expect = c[0] * x.x * x.x + c[1] * x.y * x.y + c[2] * x.z * x.z +
                          c[3] * x.x * x.y + c[4] * x.y * x.z + c[5] * x.z * x.x + c[6] * x.x +
                          c[7] * x.y + c[8] * x.z + c[9];
    EXPECT_NEAR(p.q.value(x), expect, 1e-12 * term_scale(p.q, x));
    const Vec3 g = p.q.gradient(x);
    const double h = 1e-6;
    for (int a = 0; a < 3; ++a) {
      Vec3 xp = x, xm = x;
      xp[a] += h;
      xm[a] -= h;
      EXPECT_NEAR(g[a], (p.q.value(xp) - p.q.value(xm)) / (2 * h), 1e-6 * (1 + length(g)));
    }
  }
}

TEST(QuadricRaw, RejectsBadArguments) {
  const Aabb box{{0, 0, 0}, {1, 1, 1}};
  const std::array<double, 10> ok{1, 1, 1, 0, 0, 0, 0, 0, 0, -1};
  EXPECT_NO_THROW(make_raw_quadric(ok, box, {}));
  std::array<double, 10> zero{};
  EXPECT_THROW(make_raw_quadric(zero, box, {}), std::invalid_argument);
  zero[kJ] = 1;  // J alone has no surface
  EXPECT_THROW(make_raw_quadric(zero, box, {}), std::invalid_argument);
  for (int i = 0; i < 10; ++i) {
    std::array<double, 10> bad = ok;
    bad[size_t(i)] = kNaN;
    EXPECT_THROW(make_raw_quadric(bad, box, {}), std::invalid_argument) << i;
    bad[size_t(i)] = -kInf;
    EXPECT_THROW(make_raw_quadric(bad, box, {}), std::invalid_argument) << i;
  }
  EXPECT_THROW(make_raw_quadric(ok, Aabb{}, {}), std::invalid_argument);
  EXPECT_THROW(make_raw_quadric(ok, Aabb{{0, 2, 0}, {1, 1, 1}}, {}), std::invalid_argument);
  EXPECT_THROW(make_raw_quadric(ok, Aabb{{0, 0, 0}, {1, 1, kInf}}, {}), std::invalid_argument);
  EXPECT_THROW(make_raw_quadric(ok, box, {HalfSpace{{0, 0, 0}, 1}}), std::invalid_argument);
  EXPECT_THROW(make_raw_quadric(ok, box, {HalfSpace{{kNaN, 0, 1}, 1}}), std::invalid_argument);
  EXPECT_THROW(make_raw_quadric(ok, box, {HalfSpace{{0, 0, 1}, kInf}}), std::invalid_argument);
  EXPECT_NO_THROW(make_raw_quadric(ok, box, {HalfSpace{{0, 0, 1e-200}, 0}}));  // tiny, but not zero
}

TEST(QuadricValidate, CatchesCorruptedLoadedData) {
  Primitive p = make_sphere({0, 0, 0}, 1);
  EXPECT_NO_THROW(validate(p));
  Primitive bad = p;
  bad.q.c[kE] = kNaN;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad = p;
  bad.bounds = Aabb{};
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad = p;
  bad.bounds.hi.y = kInf;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad = p;
  bad.q.c = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad = p;
  bad.clips.push_back({{0, 0, 0}, 0});
  EXPECT_THROW(validate(bad), std::invalid_argument);
}

TEST(QuadricTranslated, SameSurfaceInShiftedCoordinates) {
  std::mt19937 rng(12);
  for (int i = 0; i < 2000; ++i) {
    Quadric q;
    for (double& x : q.c) x = uniform(rng, -2, 2);
    const Vec3 c = random_point(rng, log_uniform(rng, -1, 3)), x = c + random_point(rng, 2);
    const Quadric t = q.translated(c);
    for (int k = kA; k <= kF; ++k)
      EXPECT_EQ(t.c[size_t(k)], q.c[size_t(k)]);  // quadratic part unchanged
    ASSERT_NEAR(t.value(x - c), q.value(x), 1e-13 * term_scale(q, x)) << i;
    EXPECT_NEAR(t.c[kJ], q.value(c), 1e-15 * term_scale(q, c));
    const HalfSpace h{random_unit(rng), uniform(rng, -5, 5)};
    ASSERT_NEAR(h.translated(c).eval(x - c), h.eval(x), 1e-13 * (max_abs(x) + std::abs(h.d)));
  }
  // A far sphere re-centred on itself is the textbook sphere at the origin.
  const Primitive s = make_sphere({1e4, -2e4, 3e4}, 2);
  EXPECT_TRUE(CoefficientsMatch(s.q.translated(s.p0), {1, 1, 1, 0, 0, 0, 0, 0, 0, -4}, 1e-6));
}

TEST(QuadricFrame, AlongIsOrthonormalForEveryAxis) {
  std::mt19937 rng(11);
  std::vector<Vec3> axes = test_axes(rng);
  for (int i = 0; i < 1000; ++i) axes.push_back(random_unit(rng));
  for (const Vec3& ax : axes) {
    const Frame f = Frame::along({1, 2, 3}, ax);
    EXPECT_NEAR(length(f.ex), 1, 1e-14);
    EXPECT_NEAR(length(f.ey), 1, 1e-14);
    EXPECT_NEAR(length(f.ez), 1, 1e-14);
    EXPECT_NEAR(dot(f.ex, f.ey), 0, 1e-14);
    EXPECT_NEAR(dot(f.ey, f.ez), 0, 1e-14);
    EXPECT_NEAR(dot(f.ez, f.ex), 0, 1e-14);
    EXPECT_GE(dot(f.ez, normalize(ax)), 1 - 1e-14);
    EXPECT_GE(dot(cross(f.ex, f.ey), f.ez), 1 - 1e-14);  // right-handed
  }
}

TEST(VertexNormals, KeptUnitLengthWhenAllLieOnOneSideOfTheFace) {
  const Primitive t = make_polygon({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}});  // the face's normal is +z
  const std::vector<Vec3> up = vertex_normals(t, {{-1, 0, 1}, {1, 0, 1}, {0, 3, 3}});
  ASSERT_EQ(up.size(), 3u);
  EXPECT_NEAR(length(up[2]), 1, 1e-15);
  EXPECT_EQ(vertex_normals(t, {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}}).size(), 3u);  // all below
}

TEST(VertexNormals, FlatWhenTheyStraddleOrLieInTheFace) {
  // SPD teapot's rim: normals on both sides of the face, whose blend vanishes inside it.
  const Primitive t = make_polygon({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}});
  EXPECT_TRUE(vertex_normals(t, {{0, 0, 1}, {0, 0, 1}, {0, 0, -1}}).empty());
  EXPECT_TRUE(vertex_normals(t, {{0, 0, 1}, {0, 0, 1}, {1, 0, 0}}).empty());  // one edge-on
  EXPECT_TRUE(vertex_normals(t, {{0, 0, 1}, {0, 0, 0}, {0, 0, 1}}).empty());  // one zero
  EXPECT_TRUE(vertex_normals(t, {{0, 0, 1}, {0, 0, 1}}).empty());             // too few
}

TEST(QuadricNames, EveryKindHasAName) {
  for (ShapeKind k : {ShapeKind::Sphere, ShapeKind::Ellipsoid, ShapeKind::Cylinder, ShapeKind::Cone,
                      ShapeKind::Plane, ShapeKind::Paraboloid, ShapeKind::Hyperboloid1,
                      ShapeKind::Hyperboloid2, ShapeKind::Polygon, ShapeKind::Raw})
    EXPECT_STRNE(shape_name(k), "?");
  EXPECT_STREQ(shape_name(ShapeKind::Sphere), "sphere");
  EXPECT_STREQ(shape_name(ShapeKind::Cylinder), "cylinder");
}

}  // namespace
}  // namespace rtm
