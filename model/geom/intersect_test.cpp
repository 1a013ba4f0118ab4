// The MAC schedule, the root unit and the window logic of ray/primitive intersection.
#include "geom/intersect.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <tuple>
#include <vector>
#include "geom/test_random.h"

namespace rtm {
namespace {

using namespace rtm::test;

Vec3 random_point(std::mt19937& rng, double scale) {
  return Vec3{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)} * scale;
}

/// ±m·2^e, m with `bits` significant bits (the top one set), e in [e_lo, e_lo + e_count): exact
/// in few bits. Drawn sign, e, then m (test_random.h says why).
double random_exact(std::mt19937& rng, int bits, int e_lo, int e_count) {
  const double sign = random_sign(rng);
  const int e = int(rng() % unsigned(e_count)) + e_lo;
  if (bits == 1) return sign * std::ldexp(1.0, e);
  const unsigned top = 1u << (bits - 1);
  return sign * std::ldexp(double(top + rng() % top), e);
}

Quadric random_quadric(std::mt19937& rng) {
  Quadric q;
  const double scale = log_uniform(rng, -2, 2);
  for (double& c : q.c) {
    const double x = uniform(rng, -1, 1) * scale;
    c = x * (rng() % 5 == 0 ? 0.0 : 1.0);  // some exact zeros
  }
  return q;
}

/// The paper's formulas, evaluated straightforwardly in long double.
struct AbgRef {
  long double a, b, g;
};
AbgRef abg_reference(const Quadric& q, const Vec3& u, const Vec3& v) {
  const long double A = q.c[kA], B = q.c[kB], C = q.c[kC], D = q.c[kD], E = q.c[kE], F = q.c[kF],
                    G = q.c[kG], H = q.c[kH], I = q.c[kI], J = q.c[kJ];
  const long double ux = u.x, uy = u.y, uz = u.z, vx = v.x, vy = v.y, vz = v.z;
  AbgRef r;
  r.a = A * ux * ux + B * uy * uy + C * uz * uz + D * ux * uy + E * uy * uz + F * uz * ux;
  r.b = 2 * A * ux * vx + 2 * B * uy * vy + 2 * C * uz * vz + D * (ux * vy + uy * vx) +
        E * (uy * vz + uz * vy) + F * (uz * vx + ux * vz) + G * ux + H * uy + I * uz;
  r.g = A * vx * vx + B * vy * vy + C * vz * vz + D * vx * vy + E * vy * vz + F * vz * vx + G * vx +
        H * vy + I * vz + J;
  return r;
}

/// Σ|product| for each of α, β, γ: the scale of their rounding error.
template <class Real>
Abg<double> abs_sums(const Latches<Real>& l, const CoefRam<Real>& ram) {
  double acc[3] = {0, 0, 0};
  for (const MacOp& op : kMacSchedule)
    acc[op.sum] += std::abs(double(l[op.x]) * double(l[op.y]) * double(ram[op.w]));
  return {acc[0], acc[1], acc[2]};
}

double term_scale(const Quadric& q, const Vec3& p) {
  const auto& c = q.c;
  return std::abs(c[kA] * p.x * p.x) + std::abs(c[kB] * p.y * p.y) + std::abs(c[kC] * p.z * p.z) +
         std::abs(c[kD] * p.x * p.y) + std::abs(c[kE] * p.y * p.z) + std::abs(c[kF] * p.z * p.x) +
         std::abs(c[kG] * p.x) + std::abs(c[kH] * p.y) + std::abs(c[kI] * p.z) + std::abs(c[kJ]);
}

// ---------------------------------------------------------------------------------------------
// The MAC schedule

TEST(MacSchedule, SixTwelveTenProducts) {
  int n[3] = {0, 0, 0};
  for (const MacOp& op : kMacSchedule) ++n[op.sum];
  EXPECT_EQ(n[kAlpha], 6);
  EXPECT_EQ(n[kBeta], 12);
  EXPECT_EQ(n[kGamma], 10);
  EXPECT_EQ(kMacProducts, 28);
  EXPECT_EQ(kMacSchedule.size(), 28u);
  // Issue order: all of α, then β, then γ.
  for (size_t i = 0; i < kMacSchedule.size(); ++i) {
    const Sum expect = i < 6 ? kAlpha : (i < 18 ? kBeta : kGamma);
    EXPECT_EQ(kMacSchedule[i].sum, expect) << "op " << i;
  }
}

TEST(MacSchedule, OperandsAreWhereThePaperSays) {
  const auto is_u = [](Latch x) { return x == kUx || x == kUy || x == kUz; };
  std::set<std::tuple<int, int, int, int>> seen;
  for (const MacOp& op : kMacSchedule) {
    ASSERT_LE(int(op.x), int(kOne));
    ASSERT_LE(int(op.y), int(kOne));
    ASSERT_LT(int(op.w), kRamWords);
    const int u_count = int(is_u(op.x)) + int(is_u(op.y));
    switch (op.sum) {
      case kAlpha:
        EXPECT_EQ(u_count, 2);
        break;  // α is quadratic in U
      case kBeta:
        EXPECT_EQ(u_count, 1);
        break;  // β is linear in U
      case kGamma:
        EXPECT_EQ(u_count, 0);
        break;  // γ has no U
    }
    // Each product appears once (operand order ignored).
    const int lo = std::min(int(op.x), int(op.y)), hi = std::max(int(op.x), int(op.y));
    EXPECT_TRUE(seen.insert({lo, hi, int(op.w), int(op.sum)}).second) << "duplicate product";
  }
}

TEST(MacSchedule, LoadRamHoldsPrescaledWords) {
  std::mt19937 rng(20);
  for (int i = 0; i < 100; ++i) {
    const Quadric q = random_quadric(rng);
    const CoefRam<double> rd = load_ram<double>(q);
    const CoefRam<float> rf = load_ram<float>(q);
    for (int k = 0; k < 10; ++k) {
      EXPECT_EQ(rd[size_t(k)], q.c[size_t(k)]);
      EXPECT_EQ(rf[size_t(k)], static_cast<float>(q.c[size_t(k)]));
    }
    EXPECT_EQ(rd[kRam2A], 2 * q.c[kA]);
    EXPECT_EQ(rd[kRam2B], 2 * q.c[kB]);
    EXPECT_EQ(rd[kRam2C], 2 * q.c[kC]);
    EXPECT_EQ(rf[kRam2C], 2 * static_cast<float>(q.c[kC]));
  }
  const Latches<float> l = load_latches<float>({1, 2, 3}, {4, 5, 6});
  EXPECT_EQ(l[kUx], 1.0f);
  EXPECT_EQ(l[kVz], 6.0f);
  EXPECT_EQ(l[kOne], 1.0f);
}

TEST(MacSchedule, ExactOnSmallIntegers) {
  // With small integer operands every product and sum is exact, so the schedule must give the
  // polynomial's coefficients exactly: any wrong operand shows.
  std::mt19937 rng(21);
  std::uniform_int_distribution<int> small(-9, 9);
  for (int i = 0; i < 3000; ++i) {
    Quadric q;
    for (double& c : q.c) c = small(rng);
    // z drawn first, then y, then x (test_random.h says why).
    const auto small_zyx = [&] {
      const double z = small(rng), y = small(rng);
      return Vec3{double(small(rng)), y, z};
    };
    const Vec3 u = small_zyx(), v = small_zyx();
    const Abg<double> abg = form_abg(load_latches<double>(u, v), load_ram<double>(q));
    const AbgRef ref = abg_reference(q, u, v);
    ASSERT_EQ(abg.a, double(ref.a));
    ASSERT_EQ(abg.b, double(ref.b));
    ASSERT_EQ(abg.g, double(ref.g));
    // And α t² + β t + γ is Q(V + t U) exactly, at integer t.
    for (int t : {-3, 1, 4})
      ASSERT_EQ(abg.a * t * t + abg.b * t + abg.g, q.value(v + double(t) * u));
    const Abg<float> abgf = form_abg(load_latches<float>(u, v), load_ram<float>(q));
    ASSERT_EQ(double(abgf.a), abg.a);
    ASSERT_EQ(double(abgf.b), abg.b);
    ASSERT_EQ(double(abgf.g), abg.g);
  }
}

/// The unrolled forms the simulators use give the schedule's sums bit for bit: the masked one
/// for the full schedule and for sparse ones, the reference's for any finite input.
template <class Real>
void expect_unrolled_forms_match(uint32_t seed) {
  std::mt19937 rng(seed);
  for (int i = 0; i < 4000; ++i) {
    Quadric q;
    for (double& c : q.c) c = (rng() % 3 == 0) ? 0.0 : signed_log_uniform(rng, -3, 3);
    if (i % 2) q.c[3] = q.c[4] = q.c[5] = 0;        // no cross terms: the reference's short form
    const Vec3 origin = uniform_zyx(rng, -50, 50);  // before the direction (test_random.h says why)
    const Latches<Real> l = load_latches<Real>(random_unit(rng), origin);
    const CoefRam<Real> ram = load_ram<Real>(q);
    const Abg<Real> full = form_abg(l, ram), sparse = form_abg(l, ram, sparse_ops(ram));
    for (const Abg<Real>& got : {form_abg(l, ram, kAllProducts), form_abg_fast(l, ram)}) {
      ASSERT_EQ(std::memcmp(&got, &full, sizeof full), 0) << i;
    }
    const Abg<Real> masked = form_abg(l, ram, sparse_mask(ram));
    ASSERT_EQ(std::memcmp(&masked, &sparse, sizeof sparse), 0) << i;
  }
}

TEST(MacSchedule, UnrolledFormsGiveTheScheduleSums) {
  expect_unrolled_forms_match<float>(5);
  expect_unrolled_forms_match<double>(6);
}

TEST(IntersectAbg, DoubleMatchesSubstitution) {
  std::mt19937 rng(22);
  for (int i = 0; i < 5000; ++i) {
    const Quadric q = random_quadric(rng);
    const double size = log_uniform(rng, -1, 1);  // before the direction (test_random.h says why)
    const Vec3 u = random_unit(rng) * size;
    const Vec3 v = random_point(rng, log_uniform(rng, -1, 3));
    const Latches<double> l = load_latches<double>(u, v);
    const CoefRam<double> ram = load_ram<double>(q);
    const Abg<double> abg = form_abg(l, ram);
    const Abg<double> mag = abs_sums(l, ram);
    const AbgRef ref = abg_reference(q, u, v);
    ASSERT_LE(std::abs(abg.a - double(ref.a)), 1e-14 * mag.a + 1e-300) << i;
    ASSERT_LE(std::abs(abg.b - double(ref.b)), 1e-14 * mag.b + 1e-300) << i;
    ASSERT_LE(std::abs(abg.g - double(ref.g)), 1e-14 * mag.g + 1e-300) << i;
    for (double t : {-1.7, 0.35, 2.9}) {
      const Vec3 p = v + t * u;
      const double poly = (abg.a * t + abg.b) * t + abg.g;
      const double scale = mag.a * t * t + mag.b * std::abs(t) + mag.g + term_scale(q, p);
      ASSERT_LE(std::abs(poly - q.value(p)), 1e-13 * scale + 1e-300) << "case " << i << " t " << t;
    }
  }
}

TEST(IntersectAbg, FloatMatchesSubstitution) {
  std::mt19937 rng(23);
  for (int i = 0; i < 5000; ++i) {
    const Quadric q = random_quadric(rng);
    const Vec3 u = random_unit(rng);
    const Vec3 v = random_point(rng, log_uniform(rng, -1, 2));
    const Latches<float> l = load_latches<float>(u, v);
    const CoefRam<float> ram = load_ram<float>(q);
    const Abg<float> abg = form_abg(l, ram);
    const Abg<double> mag = abs_sums(l, ram);
    // Reference from the float-rounded operands, in long double.
    Quadric qf;
    for (int k = 0; k < 10; ++k) qf.c[size_t(k)] = ram[size_t(k)];
    const AbgRef ref = abg_reference(qf, {l[kUx], l[kUy], l[kUz]}, {l[kVx], l[kVy], l[kVz]});
    // 12 products, each rounded twice, and the running sum: well under 16 ulps of Σ|product|.
    const double tol = 16 * std::numeric_limits<float>::epsilon();
    ASSERT_LE(std::abs(double(abg.a) - double(ref.a)), tol * mag.a + 1e-30) << i;
    ASSERT_LE(std::abs(double(abg.b) - double(ref.b)), tol * mag.b + 1e-30) << i;
    ASSERT_LE(std::abs(double(abg.g) - double(ref.g)), tol * mag.g + 1e-30) << i;
    for (double t : {-1.7, 0.35, 2.9}) {
      const Vec3 p = Vec3(l[kVx], l[kVy], l[kVz]) + t * Vec3(l[kUx], l[kUy], l[kUz]);
      const double poly = (double(abg.a) * t + double(abg.b)) * t + double(abg.g);
      const double scale = mag.a * t * t + mag.b * std::abs(t) + mag.g;
      ASSERT_LE(std::abs(poly - qf.value(p)), tol * scale + 1e-12 * term_scale(qf, p) + 1e-30) << i;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The root unit

template <class Real>
bool no_nan(const Roots<Real>& r) {
  return !std::isnan(r.t0) && !std::isnan(r.t1);
}

TEST(Roots, CancellationExactSmallRoot) {
  // (t − 2⁻²⁰)(t − 2³⁰): b = −(2³⁰ + 2⁻²⁰) and c = 2¹⁰ are exact; β² ≫ 4αγ.
  const double small = std::ldexp(1.0, -20), big = std::ldexp(1.0, 30);
  const Roots<double> r = solve_quadratic(1.0, -(big + small), big * small);
  ASSERT_EQ(r.n, 2);
  EXPECT_NEAR(r.t0, small, 1e-12 * small);
  EXPECT_NEAR(r.t1, big, 1e-12 * big);
}

TEST(Roots, CancellationRandom) {
  std::mt19937 rng(24);
  for (int i = 0; i < 5000; ++i) {
    const double rs = signed_log_uniform(rng, -9, -4);
    const double rb = signed_log_uniform(rng, 4, 8);
    const double a = signed_log_uniform(rng, -1, 1);
    const double b = -a * (rs + rb), c = a * rs * rb;
    // Exact roots of the rounded coefficients, in long double; the small one is −c/b to first
    // order.
    const long double la = a, lb = b, lc = c;
    const long double sq = std::sqrt(lb * lb - 4 * la * lc);
    const long double q = -(lb + (lb < 0 ? -sq : sq)) / 2;
    const long double small = lc / q, large = q / la;
    const Roots<double> r = solve_quadratic(a, b, c);
    ASSERT_EQ(r.n, 2);
    const double got_small = std::abs(r.t0) < std::abs(r.t1) ? r.t0 : r.t1;
    const double got_large = std::abs(r.t0) < std::abs(r.t1) ? r.t1 : r.t0;
    ASSERT_LE(std::abs(got_small - double(small)), 1e-12 * std::abs(double(small))) << i;
    ASSERT_LE(std::abs(got_large - double(large)), 1e-12 * std::abs(double(large))) << i;
    // And those are the intended roots, to rounding of the coefficients.
    ASSERT_LE(std::abs(got_small - rs), 1e-12 * std::abs(rs)) << i;
    ASSERT_LE(r.t0, r.t1);
  }
}

TEST(Roots, TangentIsAnExactDoubleRoot) {
  for (auto abc :
       std::vector<std::array<double, 3>>{{1, 2, 1}, {4, -12, 9}, {-1, 2, -1}, {0.25, 1, 1}}) {
    const Roots<double> r = solve_quadratic(abc[0], abc[1], abc[2]);
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t0, r.t1);
    EXPECT_EQ(r.t0, -abc[1] / (2 * abc[0]));
  }
  // b = 2 + 2⁻²⁵, c = b²/4 = 1 + 2⁻²⁵ + 2⁻⁵²: all exact, Δ == 0 exactly.
  const double b = 2 + std::ldexp(1.0, -25), c = 1 + std::ldexp(1.0, -25) + std::ldexp(1.0, -52);
  ASSERT_EQ(b * b - 4 * c, 0.0);
  const Roots<double> r = solve_quadratic(1.0, b, c);
  ASSERT_EQ(r.n, 2);
  EXPECT_EQ(r.t0, -b / 2);
  EXPECT_EQ(r.t1, -b / 2);
  // Random exact tangents a (t − r)²: a with 8 significant bits, r with 16, so b², 4ac exact.
  std::mt19937 rng(25);
  for (int i = 0; i < 3000; ++i) {
    const double a = random_exact(rng, 8, -17, 20);
    const double root = random_exact(rng, 16, -25, 30);
    const double bb = -2 * a * root, cc = a * root * root;
    ASSERT_EQ(bb * bb - 4 * a * cc, 0.0);
    const Roots<double> rr = solve_quadratic(a, bb, cc);
    ASSERT_EQ(rr.n, 2);
    ASSERT_EQ(rr.t0, root);
    ASSERT_EQ(rr.t1, root);
  }
  // float: a with 4 significant bits, r with 6, so b² and 4ac are exact in float.
  for (int i = 0; i < 3000; ++i) {
    const float a = float(random_exact(rng, 4, -9, 12));
    const float root = float(random_exact(rng, 6, -8, 12));
    const float bb = -2 * a * root, cc = a * root * root;
    ASSERT_EQ(bb * bb - 4 * a * cc, 0.0f);
    const Roots<float> rf = solve_quadratic(a, bb, cc);
    ASSERT_TRUE(no_nan(rf));
    ASSERT_EQ(rf.n, 2);
    ASSERT_EQ(rf.t0, root);
    ASSERT_EQ(rf.t1, root);
  }
}

template <class Real>
void near_tangent_case(Real a, Real root, int units, std::mt19937& rng) {
  // a (t − root)² ∓ δ with a a power of two: b², 4ac and their difference are all exact, so the
  // discriminant is exactly ±4aδ.
  (void)rng;
  const Real b = -2 * a * root, c = a * root * root;
  const Real delta = units * (std::nextafter(std::abs(c), Real(INFINITY)) - std::abs(c));
  // Hit side: a (t − root)² = δ·sign(a), two close roots.
  const Real c_hit = c - (a > 0 ? delta : -delta);
  ASSERT_GT(b * b - 4 * a * c_hit, 0);
  const Roots<Real> hit = solve_quadratic(a, b, c_hit);
  ASSERT_TRUE(no_nan(hit));
  ASSERT_EQ(hit.n, 2);
  const long double half = std::sqrt((long double)delta / std::abs((long double)a));
  const long double eps = std::numeric_limits<Real>::epsilon();
  ASSERT_LT(hit.t0, hit.t1);
  ASSERT_NEAR(double(hit.t0), double(root - half), double(8 * eps * std::abs(root)));
  ASSERT_NEAR(double(hit.t1), double(root + half), double(8 * eps * std::abs(root)));
  // Miss side: no real roots.
  const Real c_miss = c + (a > 0 ? delta : -delta);
  ASSERT_LT(b * b - 4 * a * c_miss, 0);
  const Roots<Real> miss = solve_quadratic(a, b, c_miss);
  ASSERT_EQ(miss.n, 0);
}

TEST(Roots, NearTangentBothSides) {
  std::mt19937 rng(26);
  for (int i = 0; i < 3000; ++i) {
    SCOPED_TRACE(i);
    const double a = random_exact(rng, 1, -10, 20);
    const double root = random_exact(rng, 20, -30, 30);
    near_tangent_case<double>(a, root, 1 + int(rng() % 7), rng);
    const float af = float(random_exact(rng, 1, -5, 10));
    const float rootf = float(random_exact(rng, 10, -12, 16));
    near_tangent_case<float>(af, rootf, 1 + int(rng() % 7), rng);
  }
}

TEST(Roots, GrazingRaysOnASphere) {
  // A ray passing the unit sphere's centre at distance 1 ± ε: hit just inside, miss just outside.
  std::mt19937 rng(27);
  const Primitive s = make_sphere({0, 0, 0}, 1);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 d = random_unit(rng);
    Vec3 side = random_unit(rng);
    side = normalize(side - dot(side, d) * d);
    for (double eps : {1e-6, -1e-6}) {
      const Vec3 o = (1 - eps) * side - 5.0 * d;
      const Abg<double> abg = form_abg(load_latches<double>(d, o), load_ram<double>(s.q));
      const Roots<double> r = solve_quadratic(abg.a, abg.b, abg.g);
      ASSERT_TRUE(no_nan(r));
      ASSERT_EQ(r.n, eps > 0 ? 2 : 0) << i;
      if (r.n == 2) {
        const double half = std::sqrt(1 - (1 - eps) * (1 - eps));
        ASSERT_NEAR(r.t0, 5 - half, 1e-9);
        ASSERT_NEAR(r.t1, 5 + half, 1e-9);
      }
    }
    for (double eps : {1e-2, -1e-2}) {  // float32 resolves a 1 % graze
      const Vec3 o = (1 - eps) * side - 5.0 * d;
      const Abg<float> abg = form_abg(load_latches<float>(d, o), load_ram<float>(s.q));
      const Roots<float> r = solve_quadratic(abg.a, abg.b, abg.g);
      ASSERT_TRUE(no_nan(r));
      ASSERT_EQ(r.n, eps > 0 ? 2 : 0) << i;
    }
  }
}

TEST(Roots, LinearCase) {
  Roots<double> r = solve_quadratic(0.0, 2.0, -4.0);
  EXPECT_EQ(r.n, 1);
  EXPECT_EQ(r.t0, 2.0);
  EXPECT_EQ(r.t1, 2.0);
  r = solve_quadratic(-0.0, -0.5, 1.0);
  EXPECT_EQ(r.n, 1);
  EXPECT_EQ(r.t0, 2.0);
  // α = 0 and β = 0: no roots, whatever γ is.
  EXPECT_EQ(solve_quadratic(0.0, 0.0, 3.0).n, 0);
  EXPECT_EQ(solve_quadratic(0.0, 0.0, 0.0).n, 0);
  EXPECT_EQ(solve_quadratic(0.0, -0.0, -0.0).n, 0);
  const Roots<float> rf = solve_quadratic(0.0f, 4.0f, 1.0f);
  EXPECT_EQ(rf.n, 1);
  EXPECT_EQ(rf.t0, -0.25f);
}

TEST(Roots, DoubleRootAtZero) {
  for (double a : {3.0, -2.0, 1e-300, 1e300}) {
    for (double b : {0.0, -0.0}) {
      const Roots<double> r = solve_quadratic(a, b, 0.0);
      ASSERT_TRUE(no_nan(r));
      EXPECT_EQ(r.n, 2);
      EXPECT_EQ(r.t0, 0.0);
      EXPECT_EQ(r.t1, 0.0);
    }
  }
  const Roots<float> rf = solve_quadratic(5.0f, -0.0f, 0.0f);
  ASSERT_TRUE(no_nan(rf));
  EXPECT_EQ(rf.n, 2);
  EXPECT_EQ(rf.t0, 0.0f);
  EXPECT_EQ(rf.t1, 0.0f);
}

TEST(Roots, NegativeDiscriminantAndSymmetricRoots) {
  EXPECT_EQ(solve_quadratic(1.0, 0.0, 1.0).n, 0);
  EXPECT_EQ(solve_quadratic(1.0, 1.0, 1.0).n, 0);
  EXPECT_EQ(solve_quadratic(-1.0, 1.0, -1.0).n, 0);
  EXPECT_EQ(solve_quadratic(1.0f, 0.0f, 1e-30f).n, 0);
  for (double b : {0.0, -0.0}) {
    const Roots<double> r = solve_quadratic(1.0, b, -4.0);
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t0, -2.0);
    EXPECT_EQ(r.t1, 2.0);
  }
  const Roots<double> r = solve_quadratic(-1.0, 0.0, 4.0);  // α < 0
  ASSERT_EQ(r.n, 2);
  EXPECT_EQ(r.t0, -2.0);
  EXPECT_EQ(r.t1, 2.0);
}

TEST(Roots, RandomResidualsAndOrder) {
  std::mt19937 rng(28);
  int two = 0;
  for (int i = 0; i < 5000; ++i) {
    const auto draw = [&] {
      const double x = uniform(rng, -1, 1);
      return x * log_uniform(rng, -3, 3);
    };
    const double a = draw(), b = draw(), c = draw();
    const Roots<double> r = solve_quadratic(a, b, c);
    ASSERT_TRUE(no_nan(r));
    const bool real = b * b - 4 * a * c >= 0;
    ASSERT_EQ(r.n, real ? 2 : 0);
    if (r.n != 2) continue;
    ++two;
    ASSERT_LE(r.t0, r.t1);
    for (double t : {r.t0, r.t1}) {
      const double scale = std::abs(a) * t * t + std::abs(b * t) + std::abs(c);
      ASSERT_LE(std::abs((a * t + b) * t + c), 1e-14 * scale) << i;
    }
    const Roots<float> rf = solve_quadratic(float(a), float(b), float(c));
    ASSERT_TRUE(no_nan(rf));
    if (rf.n == 2) {
      ASSERT_LE(rf.t0, rf.t1);
      for (float t : {rf.t0, rf.t1}) {
        const double td = t, af = float(a), bf = float(b), cf = float(c);
        const double scale = std::abs(af) * td * td + std::abs(bf * td) + std::abs(cf);
        ASSERT_LE(std::abs((af * td + bf) * td + cf), 1e-6 * scale) << i;
      }
    }
  }
  EXPECT_GT(two, 1000);
}

TEST(Roots, FloatNeverNaNForFiniteInputs) {
  // Every finite float class: zeros, denormals, the extremes, and random bit patterns.
  const float big = std::numeric_limits<float>::max(),
              tiny = std::numeric_limits<float>::denorm_min(),
              norm = std::numeric_limits<float>::min();
  const std::vector<float> special = {0.0f,  -0.0f, 1.0f,  -1.0f, big,    -big,  tiny,
                                      -tiny, norm,  -norm, 3e19f, -3e19f, 1e-20f};
  const auto check = [](float a, float b, float c) {
    const Roots<float> r = solve_quadratic(a, b, c);
    ASSERT_TRUE(no_nan(r)) << a << " " << b << " " << c;
    ASSERT_GE(r.n, 0);
    ASSERT_LE(r.n, 2);
    if (r.n == 2) {
      ASSERT_LE(r.t0, r.t1) << a << " " << b << " " << c;
    }
  };
  for (float a : special)
    for (float b : special)
      for (float c : special) check(a, b, c);
  std::mt19937 rng(29);
  const auto random_finite = [&rng]() {
    for (;;) {
      const uint32_t bits = uint32_t(rng());
      float f;
      std::memcpy(&f, &bits, sizeof f);
      if (std::isfinite(f)) return f;
    }
  };
  for (int i = 0; i < 20000; ++i) {
    const float c = random_finite(), b = random_finite();  // c first (test_random.h says why)
    check(random_finite(), b, c);
  }
  // Double too.
  for (int i = 0; i < 5000; ++i) {
    const auto draw = [&] {
      const int e = int(rng() % 2000) - 1000;  // before the significand (test_random.h says why)
      return std::ldexp(uniform(rng, -1, 1), e);
    };
    const double a = draw(), b = draw(), c = draw();
    const Roots<double> r = solve_quadratic(a, b, c);
    ASSERT_TRUE(no_nan(r));
    if (r.n == 2) {
      ASSERT_LE(r.t0, r.t1);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// first_hit_in_window and intersect

template <class Real>
PrimitiveHit hit_of(const Primitive& p, const Vec3& o, const Vec3& d, double t_min, double lo,
                    double hi) {
  return intersect<Real>(p, load_ram<Real>(p.q), load_latches<Real>(d, o), t_min, lo, hi);
}

TEST(IntersectWindow, NearRootClippedFarRootReturned) {
  // Cylinder x² + y² = 1, 0 <= z <= 2. The ray meets the infinite quadric first at z = 2.5
  // (past the top cap) and then at z = 1.5 (kept): the inside of the tube is hit.
  const Primitive cyl = make_cone({0, 0, 0}, 1, {0, 0, 2}, 1);
  const Vec3 o{-3, 0, 3.5}, d{1, 0, -0.5};
  const PrimitiveHit h = hit_of<double>(cyl, o, d, 0, 0, kInf);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4, 1e-12);
  EXPECT_EQ(h.clip_tests, 4);  // two roots, two clips each
  const PrimitiveHit hf = hit_of<float>(cyl, o, d, 0, 0, kInf);
  ASSERT_TRUE(hf.hit);
  EXPECT_NEAR(hf.t, 4, 1e-5);
  // Both roots clipped: no hit.
  const PrimitiveHit none = hit_of<double>(cyl, {-3, 0, 5}, {1, 0, 0}, 0, 0, kInf);
  EXPECT_FALSE(none.hit);
  EXPECT_EQ(none.clip_tests, 4);
}

TEST(IntersectWindow, RootsBehindTminAreSkipped) {
  const Primitive s = make_sphere({0, 0, 0}, 1);
  // From the centre: roots −1 and 1.
  PrimitiveHit h = hit_of<double>(s, {0, 0, 0}, {1, 0, 0}, 0, 0, kInf);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 1);
  EXPECT_EQ(h.clip_tests, 0);
  // From outside, t_min past the near root: the far root.
  h = hit_of<double>(s, {-3, 0, 0}, {1, 0, 0}, 2.5, 0, kInf);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 4);
  // t_min exactly on a root skips it (a spawned ray must not hit its own origin).
  h = hit_of<double>(s, {-3, 0, 0}, {1, 0, 0}, 2, 0, kInf);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 4);
  // Past both roots: nothing.
  EXPECT_FALSE(hit_of<double>(s, {-3, 0, 0}, {1, 0, 0}, 4.5, 0, kInf).hit);
  EXPECT_FALSE(hit_of<float>(s, {-3, 0, 0}, {1, 0, 0}, 4.5, 0, kInf).hit);
}

TEST(IntersectWindow, HitOutsideTheWindowIsNotReported) {
  const Primitive s = make_sphere({0, 0, 0}, 1);
  const Vec3 o{-3, 0, 0}, d{1, 0, 0};                      // roots 2 and 4
  EXPECT_FALSE(hit_of<double>(s, o, d, 0, 0, 1.9).hit);    // before the hit
  EXPECT_FALSE(hit_of<double>(s, o, d, 0, 2.1, 3.9).hit);  // between the roots
  // The first hit is at 2; a window holding only the far root still reports nothing: the near
  // root is the ray's hit, and it lies in an earlier voxel.
  EXPECT_FALSE(hit_of<double>(s, o, d, 0, 2.5, 10).hit);
  EXPECT_FALSE(hit_of<float>(s, o, d, 0, 2.5, 10).hit);
  // Closed window: a hit exactly on either end counts.
  PrimitiveHit h = hit_of<double>(s, o, d, 0, 2, 2);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 2);
  EXPECT_TRUE(hit_of<double>(s, o, d, 0, 1, 2).hit);
  EXPECT_TRUE(hit_of<double>(s, o, d, 0, 2, 3).hit);
  EXPECT_TRUE(hit_of<float>(s, o, d, 0, 1.5, 2.5).hit);
}

TEST(IntersectWindow, TangentAndLinearHits) {
  const Primitive s = make_sphere({0, 0, 0}, 1);
  const PrimitiveHit tangent = hit_of<double>(s, {-3, 1, 0}, {1, 0, 0}, 0, 0, kInf);
  ASSERT_TRUE(tangent.hit);
  EXPECT_EQ(tangent.t, 3);
  const Primitive plane = make_plane({0, 0, 1}, -1, Aabb{{-1, -1, 0}, {1, 1, 2}});
  const PrimitiveHit h = hit_of<double>(plane, {0.5, 0.5, 3}, {0, 0, -2}, 0, 0, kInf);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 1);
  // Parallel to the plane: α = β = 0, no hit.
  EXPECT_FALSE(hit_of<double>(plane, {0.5, 0.5, 3}, {1, 0, 0}, 0, 0, kInf).hit);
  // The plane outside its box is clipped.
  EXPECT_FALSE(hit_of<double>(plane, {5, 0.5, 3}, {0, 0, -1}, 0, 0, kInf).hit);
}

TEST(IntersectWindow, RandomSpheresAgainstGeometry) {
  std::mt19937 rng(30);
  int hits = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 c = random_point(rng, 10);
    const double r = log_uniform(rng, -1, 0.5);
    const Primitive s = make_sphere(c, r);
    // Aim near the sphere so that most rays hit; some start inside.
    const Vec3 o = i % 5 ? random_point(rng, 20) : c + random_point(rng, 0.5 * r);
    const Vec3 d = normalize(c + random_point(rng, 1.3 * r) - o);
    // Geometric solution: closest approach along d.
    const long double tc = dot(c - o, d);
    const Vec3 m = o + double(tc) * d - c;
    const long double h2 = (long double)r * r - (long double)dot(m, m);
    double expect = kInf;
    if (h2 >= 0) {
      const long double h = std::sqrt(h2);
      if (tc - h > 0)
        expect = double(tc - h);
      else if (tc + h > 0)
        expect = double(tc + h);
    }
    // Skip rays whose answer hinges on rounding (grazing, or a root at the origin).
    if (std::abs(h2) < 1e-6 * r * r ||
        std::abs(std::abs(double(tc)) - std::sqrt(std::max(0.0L, h2))) < 1e-6)
      continue;
    const PrimitiveHit hd = hit_of<double>(s, o, d, 0, 0, kInf);
    ASSERT_EQ(hd.hit, expect < kInf) << i;
    if (!hd.hit) continue;
    ++hits;
    ASSERT_NEAR(hd.t, expect, 1e-9 * (1 + expect)) << i;
    const PrimitiveHit hf = hit_of<float>(s, o, d, 0, 0, kInf);
    // float32: world-space coefficients lose digits (design notes); only a loose check here.
    if (h2 > 0.05L * r * r && expect > 0.5) {
      ASSERT_TRUE(hf.hit) << i;
      ASSERT_NEAR(hf.t, expect, 1e-2 * (1 + expect)) << i;
    }
  }
  EXPECT_GT(hits, 200);
}

TEST(IntersectWindow, NearestKeptRootOnClippedShapes) {
  // Brute force: of the roots past t_min, the first inside all clips must be returned.
  std::mt19937 rng(31);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    // Each length before its direction, the apex radius before the base's (test_random.h says why).
    const Vec3 base = random_point(rng, 2);
    const double height = uniform(rng, 0.5, 3);
    const Vec3 apex = base + random_unit(rng) * height;
    const double apex_radius = i % 2 ? uniform(rng, 0, 1) : 0;
    const Primitive p = i % 2 ? make_cone(base, uniform(rng, 0.2, 1), apex, apex_radius)
                              : make_polygon({base, apex, base + random_point(rng, 2)});
    const Vec3 o = random_point(rng, 5),
               d = normalize((base + apex) / 2.0 + random_point(rng, 1) - o);
    const Latches<double> l = load_latches<double>(d, o);
    const Abg<double> abg = form_abg(l, load_ram<double>(p.q));
    const Roots<double> roots = solve_quadratic(abg.a, abg.b, abg.g);
    double expect = kInf;
    for (int k = 0; k < roots.n; ++k) {
      const double t = k == 0 ? roots.t0 : roots.t1;
      if (t > 0 && p.inside_clips(o + t * d)) {
        expect = t;
        break;
      }
    }
    const PrimitiveHit h = first_hit_in_window(p, roots, l, 0, 0, kInf);
    ASSERT_EQ(h.hit, expect < kInf);
    if (h.hit) {
      ++hits;
      ASSERT_EQ(h.t, expect);
      // Window just before / just after the hit.
      ASSERT_FALSE(first_hit_in_window(p, roots, l, 0, 0, std::nextafter(expect, 0.0)).hit);
      ASSERT_FALSE(first_hit_in_window(p, roots, l, 0, std::nextafter(expect, kInf), kInf).hit);
    }
  }
  EXPECT_GT(hits, 100);
}

TEST(IntersectWindow, MachineClipTestMatchesPrimitive) {
  std::mt19937 rng(32);
  const Primitive p = make_polygon({{0, 0, 0}, {2, 0, 0}, {2, 2, 1}, {0, 2, 1}});
  for (int i = 0; i < 3000; ++i) {
    const Vec3 o = random_point(rng, 3), d = random_unit(rng);
    const double t = uniform(rng, 0, 4);
    const Vec3 x = o + t * d;
    // Away from the boundary both precisions agree with the primitive's own test.
    double margin = kInf;
    for (const HalfSpace& h : p.clips) margin = std::min(margin, std::abs(h.eval(x)));
    if (margin < 1e-5) continue;
    EXPECT_EQ(inside_clips(p.clips, load_latches<double>(d, o), t), p.inside_clips(x));
    EXPECT_EQ(inside_clips(p.clips, load_latches<float>(d, o), float(t)), p.inside_clips(x));
  }
}

}  // namespace
}  // namespace rtm
