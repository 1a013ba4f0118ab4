// Stiff and extreme cases of the MAC and the root unit, in float (the paper-like machine) and
// double (the reference), each against an exact reference: __float128 or long double on exactly
// representable inputs, or long double geometry. docs/numerics.md has the catalogue; where the
// float machine fails, the test pins the measured failure the document states and checks the
// remedy. Cases 1, 2, 3, 4 and 6 of the catalogue (5, 7, 8, 9 are in render/stiff_scene_test.cpp,
// 10 in dda_test.cpp, 11 in scene/extreme_input_test.cpp and tb/stiff_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "geom/intersect.h"
#include "geom/numerics.h"
#include "geom/test_random.h"

namespace rtm {
namespace {

using namespace rtm::test;

using LD = long double;
using Quad = __float128;  // 113-bit significand: products of two doubles are exact

template <class Real>
constexpr double eps() {
  return std::numeric_limits<Real>::epsilon();
}

template <class Real>
bool no_nan(const Roots<Real>& r) {
  return !std::isnan(r.t0) && !std::isnan(r.t1);
}

/// The exact b² − 4ac of Real inputs (float or double), as a __float128: every product of two
/// doubles is exact in it, and so is the difference of two nearly equal ones.
template <class Real>
Quad exact_discriminant(Real a, Real b, Real c) {
  return Quad(b) * Quad(b) - Quad(4) * Quad(a) * Quad(c);
}

void report(const char* what, const Tally& t) {
  std::printf("[numerics] %-58s n=%d wrong=%.4f%% worst=%.3g\n", what, t.n, 100 * t.rate(),
              t.worst);
  ::testing::Test::RecordProperty(what, std::to_string(t.rate()) + " " + std::to_string(t.worst));
}

// ---------------------------------------------------------------------------------------------
// 1) Catastrophic cancellation

/// Near-double roots with exactly representable coefficients: c is b²/4a moved by k ulps, so the
/// exact discriminant is a few ulps of b² while b² and 4ac themselves are large.
template <class Real>
void near_double_roots(Discriminant mode, Tally& disc_err, Tally& sign, Tally& root_err, int seed) {
  std::mt19937 rng(seed);
  for (int i = 0; i < 20000; ++i) {
    const Real a = Real(signed_log_uniform(rng, -2, 2));
    const Real b = Real(signed_log_uniform(rng, -2, 2));
    const Real c0 = Real(LD(b) * LD(b) / (4 * LD(a)));
    Real c = c0;
    const int k = int(rng() % 9) - 4;  // −4 … 4 ulps: both signs of Δ, and Δ == 0
    for (int j = 0; j < std::abs(k); ++j)
      c = std::nextafter(c, k > 0 ? Real(INFINITY) : Real(-INFINITY));
    const Quad exact = exact_discriminant(a, b, c);
    const Real got = discriminant(a, b, c, mode);
    const double ex = double(exact);
    // Relative to |Δ| itself (what decides hit or miss and the roots' separation).
    const double rel = ex != 0                     ? std::abs(double(got) - ex) / std::abs(ex)
                       : std::abs(double(got)) > 0 ? 1.0
                                                   : 0.0;
    disc_err.add(rel <= 4 * eps<Real>(), rel);
    sign.add((ex > 0) == (got > 0) && (ex < 0) == (got < 0));
    // The roots −b/2a ± √Δ/2a against the exact ones, relative to the roots' size.
    const Roots<Real> r = solve_quadratic(a, b, c, mode);
    ASSERT_TRUE(no_nan(r));
    if (ex >= 0 && r.n == 2) {
      const LD mid = -LD(b) / (2 * LD(a)), half = std::sqrt(LD(ex)) / (2 * std::abs(LD(a)));
      const double e =
          double(std::max(std::abs(LD(r.t0) - (mid - half)), std::abs(LD(r.t1) - (mid + half))) /
                 std::abs(mid));
      root_err.add(e <= 16 * eps<Real>(), e);
    }
  }
}

TEST(StiffCancellation, DiscriminantNearDoubleRootsPlainAgainstFma) {
  // Paper-like unit (plain): Δ = b·b − 4a·c, two rounded products of size b², so |Δ| of a few ulps
  // of b² is lost entirely. The FMA form is within a few ulps of Δ itself.
  Tally plain_d, plain_s, plain_r, fma_d, fma_s, fma_r;
  near_double_roots<float>(Discriminant::Plain, plain_d, plain_s, plain_r, 101);
  near_double_roots<float>(Discriminant::Fma, fma_d, fma_s, fma_r, 101);
  report("1 near-double roots fp32 plain: |dDelta|/|Delta| > 4 ulp", plain_d);
  report("1 near-double roots fp32 plain: sign of Delta wrong", plain_s);
  report("1 near-double roots fp32 plain: root error / |root|", plain_r);
  report("1 near-double roots fp32 fma: |dDelta|/|Delta| > 4 ulp", fma_d);
  report("1 near-double roots fp32 fma: sign of Delta wrong", fma_s);
  report("1 near-double roots fp32 fma: root error / |root|", fma_r);
  // docs/numerics.md: plain is off by up to hundreds of |Δ| and gets Δ's sign wrong in ~11 % of
  // these cases (a tangent taken for a miss or a miss for a hit), the roots off by up to ~√ε ≈
  // 3e-4 of their size; fma is within 1 ulp of Δ and the roots within ~1 ulp.
  EXPECT_GT(plain_s.rate(), 0.05);
  EXPECT_LT(plain_s.rate(), 0.2);
  EXPECT_GT(plain_r.worst, 1e-4);
  EXPECT_EQ(fma_d.wrong, 0) << "worst " << fma_d.worst;
  EXPECT_EQ(fma_s.wrong, 0);
  EXPECT_EQ(fma_r.wrong, 0) << "worst " << fma_r.worst;

  Tally dplain_d, dplain_s, dplain_r, dfma_d, dfma_s, dfma_r;
  near_double_roots<double>(Discriminant::Plain, dplain_d, dplain_s, dplain_r, 102);
  near_double_roots<double>(Discriminant::Fma, dfma_d, dfma_s, dfma_r, 102);
  report("1 near-double roots fp64 plain: sign of Delta wrong", dplain_s);
  report("1 near-double roots fp64 fma: sign of Delta wrong", dfma_s);
  EXPECT_GT(dplain_s.rate(), 0.05);  // the same cancellation, 29 bits further down
  EXPECT_EQ(dfma_d.wrong, 0) << "worst " << dfma_d.worst;
  EXPECT_EQ(dfma_s.wrong, 0);
  EXPECT_EQ(dfma_r.wrong, 0) << "worst " << dfma_r.worst;
}

TEST(StiffCancellation, FmaDiscriminantIsExactWhereThePlainOneIs) {
  // Where b² and 4ac are exact (small integers), both forms give the exact Δ, in both precisions.
  std::mt19937 rng(103);
  for (int i = 0; i < 5000; ++i) {
    const float a = float(int(rng() % 2001) - 1000), b = float(int(rng() % 2001) - 1000),
                c = float(int(rng() % 2001) - 1000);
    ASSERT_EQ(discriminant(a, b, c, Discriminant::Plain), discriminant(a, b, c, Discriminant::Fma));
    ASSERT_EQ(double(discriminant(a, b, c, Discriminant::Fma)),
              double(exact_discriminant(a, b, c)));
    const Roots<float> p = solve_quadratic(a, b, c, Discriminant::Plain),
                       f = solve_quadratic(a, b, c, Discriminant::Fma);
    ASSERT_EQ(p.n, f.n);
    ASSERT_EQ(p.t0, f.t0);
    ASSERT_EQ(p.t1, f.t1);
  }
  // Non-finite products stay rejected, not NaN roots.
  const float big = std::numeric_limits<float>::max();
  EXPECT_EQ(solve_quadratic(big, big, -big, Discriminant::Fma).n, 0);
  EXPECT_TRUE(no_nan(solve_quadratic(1.0f, big, 1.0f, Discriminant::Fma)));
}

template <class Real>
Tally small_root_when_beta_dominates(int seed, bool naive) {
  std::mt19937 rng(seed);
  Tally t;
  for (int i = 0; i < 20000; ++i) {
    // Roots rs (tiny) and rb (huge): β² ≫ 4αγ; coefficients rounded to Real, roots of the rounded
    // coefficients in long double.
    const double rs = signed_log_uniform(rng, -6, -2), rb = signed_log_uniform(rng, 2, 6);
    const double a0 = signed_log_uniform(rng, -1, 1);
    const Real a = Real(a0), b = Real(-a0 * (rs + rb)), c = Real(a0 * rs * rb);
    const LD sq = std::sqrt(LD(b) * LD(b) - 4 * LD(a) * LD(c));
    const LD q = -(LD(b) + (b < 0 ? -sq : sq)) / 2;
    const LD small = LD(c) / q;
    Real got;
    if (naive) {  // the textbook (−b ± √Δ)/2a: the small root cancels b against √Δ
      const Real s = std::sqrt(b * b - 4 * a * c);
      const Real r0 = (-b + s) / (2 * a), r1 = (-b - s) / (2 * a);
      got = std::abs(r0) < std::abs(r1) ? r0 : r1;
    } else {
      const Roots<Real> r = solve_quadratic(a, b, c);
      got = std::abs(r.t0) < std::abs(r.t1) ? r.t0 : r.t1;
    }
    const double e = double(std::abs(LD(got) - small) / std::abs(small));
    t.add(e <= 8 * eps<Real>(), e);
  }
  return t;
}

TEST(StiffCancellation, SmallRootWhenBetaDominates) {
  const Tally stable32 = small_root_when_beta_dominates<float>(104, false);
  const Tally naive32 = small_root_when_beta_dominates<float>(104, true);
  const Tally stable64 = small_root_when_beta_dominates<double>(105, false);
  report("1 beta^2 >> 4 alpha gamma fp32 stable form: small root rel err", stable32);
  report("1 beta^2 >> 4 alpha gamma fp32 textbook form: small root rel err", naive32);
  report("1 beta^2 >> 4 alpha gamma fp64 stable form: small root rel err", stable64);
  EXPECT_EQ(stable32.wrong, 0) << stable32.worst;
  EXPECT_EQ(stable64.wrong, 0) << stable64.worst;
  EXPECT_GT(naive32.rate(), 0.9);  // why the root unit uses the stable form: the textbook one fails
  EXPECT_GT(naive32.worst, 0.5);
}

// ---------------------------------------------------------------------------------------------
// 2) β = 0, α = 0 exactly, α tiny

TEST(StiffExactZeros, BetaZeroFromTheSphereCentre) {
  // Origin at the centre of a sphere written about its centre (what re-centring stores): V = 0, so
  // β = 0 exactly and the roots are ±r/|U|, never NaN, in both precisions.
  std::mt19937 rng(110);
  for (int i = 0; i < 3000; ++i) {
    const double r = log_uniform(rng, -3, 3);
    const double size = log_uniform(rng, -2, 2);  // before the direction (test_random.h says why)
    const Vec3 u = random_unit(rng) * size;
    Quadric q;
    q.c = {1, 1, 1, 0, 0, 0, 0, 0, 0, -r * r};
    const auto check = [&](auto zero) {
      using Real = decltype(zero);
      const Latches<Real> l = load_latches<Real>(u, {0, 0, 0});
      const Abg<Real> abg = form_abg(l, load_ram<Real>(q));
      ASSERT_EQ(abg.b, Real(0));
      const Roots<Real> roots = solve_quadratic(abg.a, abg.b, abg.g);
      ASSERT_EQ(roots.n, 2);
      ASSERT_LE(std::abs(roots.t0 + roots.t1), 2 * eps<Real>() * roots.t1);  // t0 = q/α, t1 = γ/q
      const LD exact = LD(r) / std::sqrt(LD(u.x) * u.x + LD(u.y) * u.y + LD(u.z) * u.z);
      ASSERT_LE(std::abs(LD(roots.t1) - exact), 8 * eps<Real>() * exact);
      const PrimitiveHit h =
          first_hit_in_window(std::vector<HalfSpace>{}, roots, l, 0.0, 0.0, kInf);
      ASSERT_TRUE(h.hit);  // the far root: the near one is behind the origin
      ASSERT_EQ(h.t, double(roots.t1));
    };
    check(0.0f);
    check(0.0);
  }
}

TEST(StiffExactZeros, AlphaZeroPlanesAndRaysAlongACylinderAxis) {
  std::mt19937 rng(111);
  // A plane: α = 0 exactly for every ray, the linear root −γ/β.
  for (int i = 0; i < 3000; ++i) {
    const Vec3 n = random_unit(rng);
    const double size = log_uniform(rng, -2, 2);  // before the direction (test_random.h says why)
    const Vec3 u = random_unit(rng) * size, v = 10.0 * random_unit(rng);
    const double d = uniform(rng, -5, 5);
    Quadric q;
    q.c = {0, 0, 0, 0, 0, 0, n.x, n.y, n.z, d};
    const LD exact = -(LD(n.x) * v.x + LD(n.y) * v.y + LD(n.z) * v.z + d) /
                     (LD(n.x) * u.x + LD(n.y) * u.y + LD(n.z) * u.z);
    const auto check = [&](auto zero, double tol) {
      using Real = decltype(zero);
      const Abg<Real> abg = form_abg(load_latches<Real>(u, v), load_ram<Real>(q));
      ASSERT_EQ(abg.a, Real(0));
      const Roots<Real> r = solve_quadratic(abg.a, abg.b, abg.g);
      ASSERT_EQ(r.n, abg.b != 0 ? 1 : 0);
      if (r.n == 1) {  // error ≤ tol × the condition: (Σ|γ terms| + |t| Σ|β terms|) / |β|
        const double sg =
            std::abs(n.x * v.x) + std::abs(n.y * v.y) + std::abs(n.z * v.z) + std::abs(d);
        const double sb = std::abs(n.x * u.x) + std::abs(n.y * u.y) + std::abs(n.z * u.z);
        const double beta = std::abs(dot(n, u));
        ASSERT_LE(std::abs(LD(r.t0) - exact), tol * (sg + std::abs(double(exact)) * sb) / beta)
            << i;
      }
    };
    check(0.0f, 64 * eps<float>());
    check(0.0, 64 * eps<double>());
  }
  // Along an axis-aligned cylinder's axis: α = β = 0 exactly, no root however γ falls.
  Quadric cyl;
  cyl.c = {1, 1, 0, 0, 0, 0, 0, 0, 0, -1};
  for (const Vec3& v : {Vec3{0.5, 0.25, -3}, Vec3{3, 0, 0}, Vec3{1, 0, 7}}) {
    const Abg<float> f = form_abg(load_latches<float>({0, 0, 1}, v), load_ram<float>(cyl));
    EXPECT_EQ(f.a, 0.0f);
    EXPECT_EQ(f.b, 0.0f);
    EXPECT_EQ(solve_quadratic(f.a, f.b, f.g).n, 0);
    const Abg<double> d = form_abg(load_latches<double>({0, 0, -1}, v), load_ram<double>(cyl));
    EXPECT_EQ(solve_quadratic(d.a, d.b, d.g).n, 0);
  }
}

TEST(StiffExactZeros, AlphaTinyNonZeroKeepsTheNearRoot) {
  // A slightly curved plane ε x² + z = 0: the far root −β/α runs off to ±huge as ε → 0, the near
  // root stays ≈ −γ/β and comes out of c/q without cancellation, whatever ε.
  std::mt19937 rng(112);
  Tally f32, f64;
  for (int i = 0; i < 5000; ++i) {
    const double e = signed_log_uniform(rng, -30, -1);
    Quadric q;
    q.c = {e, 0, 0, 0, 0, 0, 0, 0, 1, 0};
    const Vec3 u = normalize(Vec3{uniform(rng, -1, 1), uniform(rng, -1, 1), -1});
    const Vec3 v{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, 0.5, 2)};
    // Near root of the exact polynomial in long double.
    const LD a = LD(e) * u.x * u.x, b = 2 * LD(e) * u.x * v.x + u.z, c = LD(e) * v.x * v.x + v.z;
    const LD sq = std::sqrt(b * b - 4 * a * c), qq = -(b + (b < 0 ? -sq : sq)) / 2, near = c / qq;
    const auto run = [&](auto zero, Tally& t) {
      using Real = decltype(zero);
      const Abg<Real> abg = form_abg(load_latches<Real>(u, v), load_ram<Real>(q));
      const Roots<Real> r = solve_quadratic(abg.a, abg.b, abg.g);
      ASSERT_TRUE(no_nan(r));
      ASSERT_GE(r.n, 1);
      const Real got = r.n == 1 ? r.t0 : (std::abs(r.t0) < std::abs(r.t1) ? r.t0 : r.t1);
      const double err = double(std::abs(LD(got) - near) / std::abs(near));
      t.add(err <= 64 * eps<Real>(), err);
    };
    run(0.0f, f32);
    run(0.0, f64);
  }
  report("2 alpha tiny (1e-30..1e-1) fp32: near root rel err", f32);
  report("2 alpha tiny (1e-30..1e-1) fp64: near root rel err", f64);
  EXPECT_EQ(f32.wrong, 0) << f32.worst;
  EXPECT_EQ(f64.wrong, 0) << f64.worst;
}

// ---------------------------------------------------------------------------------------------
// 3) Tangent and near-tangent rays

/// Rays passing a unit sphere's centre at distance 1 + off (off < 0: hit, off > 0: miss), from 5
/// away, origin re-centred (the default machine). Returns the misclassification tally.
template <class Real>
Tally tangents(double off, Discriminant mode, int seed, double* worst_residual) {
  std::mt19937 rng(seed);
  Quadric q;
  q.c = {1, 1, 1, 0, 0, 0, 0, 0, 0, -1};
  Tally t;
  *worst_residual = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 d = random_unit(rng);
    Vec3 side = random_unit(rng);
    side = normalize(side - dot(side, d) * d);
    const Vec3 o = (1 + off) * side - 5.0 * d;
    // Exact: the ray's closest approach to the centre, in long double from the double inputs.
    const LD od = LD(o.x) * d.x + LD(o.y) * d.y + LD(o.z) * d.z,
             dd = LD(d.x) * d.x + LD(d.y) * d.y + LD(d.z) * d.z;
    const LD oo = LD(o.x) * o.x + LD(o.y) * o.y + LD(o.z) * o.z;
    const bool exact_hit = oo - od * od / dd <= 1;
    const Latches<Real> l = load_latches<Real>(d, o);
    const Abg<Real> abg = form_abg(l, load_ram<Real>(q));
    const Roots<Real> r = solve_quadratic(abg.a, abg.b, abg.g, mode);
    EXPECT_TRUE(no_nan(r));
    EXPECT_LE(r.t0, r.t1);
    t.add((r.n == 2) == exact_hit);
    if (r.n == 2) {  // a reported hit lies on the surface to the precision's resolution
      const Vec3 p = o + double(r.t0) * d;
      *worst_residual = std::max(*worst_residual, std::abs(dot(p, p) - 1));
    }
  }
  return t;
}

TEST(StiffTangents, OffsetsOfOneInTenMillionOfTheRadius) {
  double res = 0;
  // fp64 resolves ±1e-7 of the radius exactly.
  for (double off : {-1e-7, 1e-7}) {
    const Tally t = tangents<double>(off, Discriminant::Plain, 120, &res);
    report(off < 0 ? "3 tangent -1e-7 r fp64: hit/miss wrong"
                   : "3 tangent +1e-7 r fp64: hit/miss wrong",
           t);
    EXPECT_EQ(t.wrong, 0);
    EXPECT_LT(res, 1e-12);
  }
  // fp32 cannot: Δ ≈ 8e-7 against rounding of β² ≈ 100 by ~6e-6. Never NaN, hits on the surface to
  // float resolution, but the decision is a coin toss (docs/numerics.md: ~18 % wrong on the hit
  // side, ~76 % on the miss side), and fma does not change that: the rounding is in β and γ.
  Tally in32 = tangents<float>(-1e-7, Discriminant::Plain, 121, &res);
  EXPECT_LT(res, 1e-5);
  Tally out32 = tangents<float>(1e-7, Discriminant::Plain, 122, &res);
  const Tally in32f = tangents<float>(-1e-7, Discriminant::Fma, 121, &res);
  const Tally out32f = tangents<float>(1e-7, Discriminant::Fma, 122, &res);
  report("3 tangent -1e-7 r fp32 plain: hit/miss wrong", in32);
  report("3 tangent +1e-7 r fp32 plain: hit/miss wrong", out32);
  report("3 tangent -1e-7 r fp32 fma: hit/miss wrong", in32f);
  report("3 tangent +1e-7 r fp32 fma: hit/miss wrong", out32f);
  EXPECT_GT(in32.rate() + out32.rate(), 0.2);
  EXPECT_GT(in32f.rate() + out32f.rate(), 0.2);
  // At ±1e-3 of the radius float32 is always right.
  for (double off : {-1e-3, 1e-3}) {
    EXPECT_EQ(tangents<float>(off, Discriminant::Plain, 123, &res).wrong, 0) << off;
  }
}

// ---------------------------------------------------------------------------------------------
// 4) Stiff coefficients

/// Rays at an axis-aligned ellipsoid with radii (1e3, 1, 1e-3) from all round it; hits against
/// long double geometry (the ray mapped onto the unit sphere).
template <class Real>
Tally stiff_ellipsoid(int seed, double* worst_t) {
  const Vec3 radii{1e3, 1, 1e-3};
  Quadric q;
  q.c = {1 / (radii.x * radii.x),
         1 / (radii.y * radii.y),
         1 / (radii.z * radii.z),
         0,
         0,
         0,
         0,
         0,
         0,
         -1};
  const CoefRam<Real> ram = load_ram<Real>(scaled_pow2(q));
  std::mt19937 rng(seed);
  Tally t;
  *worst_t = 0;
  for (int i = 0; i < 20000; ++i) {
    // Aim at a random point inside the box, from a random point 2 boxes away.
    const Vec3 target =
        Vec3{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)} * radii * 0.9;
    const Vec3 o =
        Vec3{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)} * radii * 1.5;
    const Vec3 d = normalize(target - o);
    const LD ox = LD(o.x) / radii.x, oy = LD(o.y) / radii.y, oz = LD(o.z) / radii.z;
    const LD dx = LD(d.x) / radii.x, dy = LD(d.y) / radii.y, dz = LD(d.z) / radii.z;
    const LD a = dx * dx + dy * dy + dz * dz, b = 2 * (ox * dx + oy * dy + oz * dz),
             c = ox * ox + oy * oy + oz * oz - 1;
    const LD disc = b * b - 4 * a * c;
    bool hit = false;
    LD t_hit = 0;
    if (disc >= 0) {
      const LD s = std::sqrt(disc), qq = -(b + (b < 0 ? -s : s)) / 2;
      LD t0 = qq / a, t1 = c / qq;
      if (t0 > t1) std::swap(t0, t1);
      if (t1 > 0) hit = true, t_hit = t0 > 0 ? t0 : t1;
    }
    const Latches<Real> l = load_latches<Real>(d, o);
    const Abg<Real> abg = form_abg(l, ram);
    const PrimitiveHit h = first_hit_in_window(
        std::vector<HalfSpace>{}, solve_quadratic(abg.a, abg.b, abg.g), l, 0.0, 0.0, kInf);
    t.add(h.hit == hit);
    if (h.hit && hit)
      *worst_t = std::max(*worst_t, double(std::abs(LD(h.t) - t_hit) / (1e3 * radii.z)));
  }
  return t;
}

TEST(StiffCoefficients, EllipsoidWithAxesThousandToOneToAThousandth) {
  double w32 = 0, w64 = 0;
  const Tally t32 = stiff_ellipsoid<float>(130, &w32), t64 = stiff_ellipsoid<double>(130, &w64);
  report("4 ellipsoid 1e3:1:1e-3 fp32: hit/miss wrong", t32);
  report("4 ellipsoid 1e3:1:1e-3 fp64: hit/miss wrong", t64);
  std::printf("[numerics] 4 ellipsoid t error / thinnest radius: fp32 %.3g, fp64 %.3g\n", w32, w64);
  EXPECT_EQ(t64.wrong, 0);
  EXPECT_LT(w64, 1e-6);
  // Coefficients span 1e-6 … 1e6 (A … C): fine in float32's range; the misses are grazing rays
  // of the 1e-3-thin disc (docs/numerics.md: < 0.1 %).
  EXPECT_LT(t32.rate(), 1e-3);
}

/// A unit sphere at (0.3, −0.2, 0.1) written with all ten coefficients multiplied by `scale`.
Quadric scaled_sphere(double scale) {
  Quadric q;
  const Vec3 c{0.3, -0.2, 0.1};
  q.c = {1, 1, 1, 0, 0, 0, -2 * c.x, -2 * c.y, -2 * c.z, dot(c, c) - 1};
  for (double& k : q.c) k *= scale;
  return q;
}

/// Rays at the sphere with coefficients × scale, in Real, coefficient RAM image as `mode` makes
/// it. wrong: hit/miss against long double geometry (grazing rays within 1e-3 excluded); t_err:
/// worst relative error of the first root.
template <class Real>
void scaled_coefficients(double scale, CoefScaling mode, Tally& wrong, double* t_err) {
  std::mt19937 rng(131);
  const Quadric q = scaled_sphere(scale);
  const CoefRam<Real> ram = load_ram<Real>(mode == CoefScaling::Pow2 ? scaled_pow2(q) : q);
  const Vec3 c{0.3, -0.2, 0.1};
  *t_err = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 o = 4.0 * random_unit(rng), d = normalize(0.9 * random_unit(rng) - o);
    const LD b = LD(o.x - c.x) * d.x + LD(o.y - c.y) * d.y + LD(o.z - c.z) * d.z;
    const LD oc =
        LD(o.x - c.x) * (o.x - c.x) + LD(o.y - c.y) * (o.y - c.y) + LD(o.z - c.z) * (o.z - c.z);
    const LD disc = b * b - (oc - 1);
    if (std::abs(double(disc)) < 1e-3) continue;
    const Latches<Real> l = load_latches<Real>(d, o);
    const Abg<Real> abg = form_abg(l, ram);
    const PrimitiveHit h = first_hit_in_window(
        std::vector<HalfSpace>{}, solve_quadratic(abg.a, abg.b, abg.g), l, 0.0, 0.0, kInf);
    wrong.add(h.hit == (disc >= 0));
    if (h.hit && disc >= 0)
      *t_err = std::max(
          *t_err, double(std::abs(LD(h.t) - (-b - std::sqrt(disc))) / (-b - std::sqrt(disc))));
  }
}

TEST(StiffCoefficients, AllTenScaledBy1ePlusMinus20) {
  Tally unit;
  double unit_err = 0;
  scaled_coefficients<float>(1, CoefScaling::None, unit, &unit_err);
  report("4 coefficients x1 fp32: hit/miss wrong", unit);
  EXPECT_EQ(unit.wrong, 0);
  for (double scale : {1e20, 1e-20, 1e30, 1e-30}) {
    Tally w_none, w_pow2, w64;
    double e_none = 0, e_pow2 = 0, e64 = 0;
    scaled_coefficients<float>(scale, CoefScaling::None, w_none, &e_none);
    scaled_coefficients<float>(scale, CoefScaling::Pow2, w_pow2, &e_pow2);
    scaled_coefficients<double>(scale, CoefScaling::None, w64, &e64);
    char s[64];
    std::snprintf(s, sizeof s, "x%g", scale);
    report((std::string("4 coefficients ") + s + " fp32 coef_scaling=none: hit/miss wrong").c_str(),
           w_none);
    report((std::string("4 coefficients ") + s + " fp32 coef_scaling=pow2: hit/miss wrong").c_str(),
           w_pow2);
    std::printf("[numerics] 4 coefficients %s fp32 t rel error: none %.3g, pow2 %.3g (x1: %.3g)\n",
                s, e_none, e_pow2, unit_err);
    // float32 without scaling: ×1e20 and ×1e30 overflow β² (Δ = inf − inf: every ray misses);
    // ×1e−20 still works (β² ≈ 1e−39 is subnormal but keeps ~20 bits); ×1e−30 underflows.
    // Measured: ×1e20, ×1e30 80 % wrong (all misses); ×1e−20 right, t error 1.1e-5; ×1e−30 20 %
    // wrong, t error 0.28.
    if (scale != 1e-20) {
      EXPECT_GT(w_none.rate(), 0.1) << s;
    } else {
      EXPECT_EQ(w_none.wrong, 0) << s;
    }
    // pow2 is as good as the unscaled unit sphere (1e±20 is not a power of two, so the words
    // round differently: compare errors, not bits).
    EXPECT_EQ(w_pow2.wrong, 0) << s;
    EXPECT_LE(e_pow2, 4 * unit_err + 1e-6) << s;
    EXPECT_EQ(w64.wrong, 0) << s;  // double's range takes 1e±30 unscaled
  }
  // Double's range ends too: ×1e±200 fails without scaling and not with it.
  for (double scale : {1e200, 1e-200}) {
    Tally w_none, w_pow2;
    double e = 0;
    scaled_coefficients<double>(scale, CoefScaling::None, w_none, &e);
    scaled_coefficients<double>(scale, CoefScaling::Pow2, w_pow2, &e);
    EXPECT_GT(w_none.rate(), 0.1) << scale;
    EXPECT_EQ(w_pow2.wrong, 0) << scale;
  }
  // A power-of-two factor (2^±66 ≈ 7e±19): pow2 gives the unscaled sphere's roots bit for bit.
  std::mt19937 rng(133);
  for (int k : {66, -66}) {
    Quadric q = scaled_sphere(1);
    for (double& c : q.c) c = std::ldexp(c, k);
    const CoefRam<float> a = load_ram<float>(scaled_pow2(scaled_sphere(1))),
                         b = load_ram<float>(scaled_pow2(q));
    for (int i = 0; i < 2000; ++i) {
      const Vec3 o = 4.0 * random_unit(rng), d = normalize(0.9 * random_unit(rng) - o);
      const Latches<float> l = load_latches<float>(d, o);
      const Abg<float> x = form_abg(l, a), y = form_abg(l, b);
      const Roots<float> rx = solve_quadratic(x.a, x.b, x.g), ry = solve_quadratic(y.a, y.b, y.g);
      ASSERT_EQ(rx.n, ry.n);
      ASSERT_EQ(rx.t0, ry.t0);
      ASSERT_EQ(rx.t1, ry.t1);
    }
  }
}

TEST(StiffCoefficients, Pow2ScalingIsExactAndLeavesOrdinaryQuadricsBitForBit) {
  std::mt19937 rng(132);
  for (int i = 0; i < 5000; ++i) {
    Quadric q;
    const double s = log_uniform(rng, -3, 3);
    for (double& c : q.c) {
      const double x = uniform(rng, -1, 1) * s;
      c = x * (rng() % 4 == 0 ? 0.0 : 1.0);
    }
    q.c[kA] = s;  // not identically zero
    const int k = pow2_scale_exponent(q);
    const Quadric p = scaled_pow2(q);
    double m = 0;
    for (int j = 0; j < 10; ++j) {
      ASSERT_EQ(p.c[size_t(j)], std::ldexp(q.c[size_t(j)], -k));
      ASSERT_EQ(std::ldexp(p.c[size_t(j)], k), q.c[size_t(j)]);  // exact
      m = std::max(m, std::abs(p.c[size_t(j)]));
    }
    ASSERT_GE(m, 1.0);
    ASSERT_LT(m, 2.0);
    // Same roots from either image, in both precisions (no intermediate leaves the range).
    const Vec3 u = random_unit(rng), v = 3.0 * random_unit(rng);
    const auto same = [&](auto zero) {
      using Real = decltype(zero);
      const Latches<Real> l = load_latches<Real>(u, v);
      const Abg<Real> x = form_abg(l, load_ram<Real>(q)), y = form_abg(l, load_ram<Real>(p));
      const Roots<Real> rx = solve_quadratic(x.a, x.b, x.g), ry = solve_quadratic(y.a, y.b, y.g);
      ASSERT_EQ(rx.n, ry.n);
      ASSERT_EQ(rx.t0, ry.t0);
      ASSERT_EQ(rx.t1, ry.t1);
    };
    same(0.0f);
    same(0.0);
  }
}

// ---------------------------------------------------------------------------------------------
// 6) Non-normalised directions

TEST(StiffDirections, LengthsFrom1eMinus4To1e4GiveTheSameHits) {
  // t scales as 1/|U|: the same hit/miss for every length, and t·|U| to the precision.
  std::mt19937 rng(160);
  Quadric q;
  q.c = {1, 1, 1, 0, 0, 0, 0, 0, 0, -1};
  Tally f32, f64;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 o = 3.0 * random_unit(rng), d = normalize(1.2 * random_unit(rng) - o);
    const LD od = LD(o.x) * d.x + LD(o.y) * d.y + LD(o.z) * d.z,
             oo = LD(o.x) * o.x + LD(o.y) * o.y + LD(o.z) * o.z;
    const LD disc = od * od - (oo - 1);
    if (std::abs(double(disc)) < 1e-3) continue;  // grazing rays belong to case 3
    const LD t_unit = disc >= 0 ? -od - std::sqrt(disc) : 0;
    for (int e = -4; e <= 4; ++e) {
      const double len = std::pow(10.0, e);
      const Vec3 u = d * len;
      const auto run = [&](auto zero, Tally& t) {
        using Real = decltype(zero);
        const Latches<Real> l = load_latches<Real>(u, o);
        const Abg<Real> abg = form_abg(l, load_ram<Real>(q));
        const PrimitiveHit h = first_hit_in_window(
            std::vector<HalfSpace>{}, solve_quadratic(abg.a, abg.b, abg.g), l, 0.0, 0.0, kInf);
        bool ok = h.hit == (disc >= 0);
        double err = 0;
        if (ok && h.hit) {
          err = double(std::abs(LD(h.t) * len - t_unit) / t_unit);
          ok = err <= 256 * eps<Real>();
        }
        t.add(ok, err);
      };
      run(0.0f, f32);
      run(0.0, f64);
    }
  }
  report("6 |U| 1e-4..1e4 fp32: hit/miss or t|U| wrong", f32);
  report("6 |U| 1e-4..1e4 fp64: hit/miss or t|U| wrong", f64);
  EXPECT_EQ(f32.wrong, 0) << f32.worst;
  EXPECT_EQ(f64.wrong, 0) << f64.worst;
}

}  // namespace
}  // namespace rtm
