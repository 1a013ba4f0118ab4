// The MAC unit's operand table: how the paper's 6 / 12 / 10 products form α, β, γ.
//
// Each product is latch(x) · latch(y) · ram(w): multiplier 1 multiplies two operands from the
// U/V latches, multiplier 2 multiplies that by one word of the coefficient RAM, the adder
// accumulates. The paper does not say how 2A·Ux·Vx, G·Ux and J are fed; here the RAM holds the
// pre-scaled words 2A, 2B, 2C and a latch holds the constant 1.0 (both exact in binary floating
// point, so the sums equal direct substitution term by term).
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "geom/quadric.h"

namespace rtm {

/// Latch operands: the ray direction U, origin V, and the constant one.
enum Latch : uint8_t { kUx, kUy, kUz, kVx, kVy, kVz, kOne };
/// Coefficient RAM words: A..J in the paper's order, then the pre-scaled 2A, 2B, 2C.
enum RamWord : uint8_t {
  kRamA,
  kRamB,
  kRamC,
  kRamD,
  kRamE,
  kRamF,
  kRamG,
  kRamH,
  kRamI,
  kRamJ,
  kRam2A,
  kRam2B,
  kRam2C
};
constexpr int kRamWords = 13;
/// Which sum a product is accumulated into.
enum Sum : uint8_t { kAlpha, kBeta, kGamma };

struct MacOp {
  Latch x, y;
  RamWord w;
  Sum sum;
};

constexpr int kAlphaProducts = 6, kBetaProducts = 12, kGammaProducts = 10;
constexpr int kMacProducts = kAlphaProducts + kBetaProducts + kGammaProducts;

/// The full schedule in issue order: α's 6, then β's 12, then γ's 10.
constexpr std::array<MacOp, kMacProducts> kMacSchedule{{
    // α = A Ux² + B Uy² + C Uz² + D Ux Uy + E Uy Uz + F Uz Ux
    {kUx, kUx, kRamA, kAlpha},
    {kUy, kUy, kRamB, kAlpha},
    {kUz, kUz, kRamC, kAlpha},
    {kUx, kUy, kRamD, kAlpha},
    {kUy, kUz, kRamE, kAlpha},
    {kUz, kUx, kRamF, kAlpha},
    // β = 2A Ux Vx + 2B Uy Vy + 2C Uz Vz + D (Ux Vy + Uy Vx) + E (Uy Vz + Uz Vy)
    //     + F (Uz Vx + Ux Vz) + G Ux + H Uy + I Uz
    {kUx, kVx, kRam2A, kBeta},
    {kUy, kVy, kRam2B, kBeta},
    {kUz, kVz, kRam2C, kBeta},
    {kUx, kVy, kRamD, kBeta},
    {kUy, kVx, kRamD, kBeta},
    {kUy, kVz, kRamE, kBeta},
    {kUz, kVy, kRamE, kBeta},
    {kUz, kVx, kRamF, kBeta},
    {kUx, kVz, kRamF, kBeta},
    {kUx, kOne, kRamG, kBeta},
    {kUy, kOne, kRamH, kBeta},
    {kUz, kOne, kRamI, kBeta},
    // γ = A Vx² + B Vy² + C Vz² + D Vx Vy + E Vy Vz + F Vz Vx + G Vx + H Vy + I Vz + J
    {kVx, kVx, kRamA, kGamma},
    {kVy, kVy, kRamB, kGamma},
    {kVz, kVz, kRamC, kGamma},
    {kVx, kVy, kRamD, kGamma},
    {kVy, kVz, kRamE, kGamma},
    {kVz, kVx, kRamF, kGamma},
    {kVx, kOne, kRamG, kGamma},
    {kVy, kOne, kRamH, kGamma},
    {kVz, kOne, kRamI, kGamma},
    {kOne, kOne, kRamJ, kGamma},
}};

template <class Real>
using CoefRam = std::array<Real, kRamWords>;
template <class Real>
using Latches = std::array<Real, 7>;

template <class Real>
CoefRam<Real> load_ram(const Quadric& q) {
  CoefRam<Real> r{};
  for (int i = 0; i < 10; ++i) r[i] = static_cast<Real>(q.c[i]);
  r[kRam2A] = 2 * r[kRamA];
  r[kRam2B] = 2 * r[kRamB];
  r[kRam2C] = 2 * r[kRamC];
  return r;
}

template <class Real>
Latches<Real> load_latches(const Vec3& dir, const Vec3& origin) {
  return {static_cast<Real>(dir.x),
          static_cast<Real>(dir.y),
          static_cast<Real>(dir.z),
          static_cast<Real>(origin.x),
          static_cast<Real>(origin.y),
          static_cast<Real>(origin.z),
          Real(1)};
}

template <class Real>
struct Abg {
  Real a = 0, b = 0, g = 0;  ///< α, β, γ of α t² + β t + γ = 0
};

/// One product as the hardware forms it: (x · y) · w, rounded after each multiply.
template <class Real>
Real mac_product(const MacOp& op, const Latches<Real>& l, const CoefRam<Real>& ram) {
  const Real m1 = l[op.x] * l[op.y];
  return m1 * ram[op.w];
}

/// α, β, γ by running the schedule in order; the clock-level MAC model must match this bit for bit.
template <class Real>
Abg<Real> form_abg(const Latches<Real>& l, const CoefRam<Real>& ram) {
  Real acc[3] = {0, 0, 0};
  for (const MacOp& op : kMacSchedule) acc[op.sum] += mac_product(op, l, ram);
  return {acc[kAlpha], acc[kBeta], acc[kGamma]};
}

/// A per-primitive schedule: indices into kMacSchedule, in schedule order.
using MacOps = std::vector<uint8_t>;

/// The sparse schedule of one RAM image: the products whose coefficient word is non-zero. A
/// skipped product is ±0, and adding ±0 to an accumulator that starts at +0 never changes it
/// (x + ±0 = x for x ≠ 0, +0 + ±0 = +0 when rounding to nearest), so the sums are bit-identical
/// to the full schedule's for finite operands.
template <class Real>
MacOps sparse_ops(const CoefRam<Real>& ram) {
  MacOps ops;
  for (size_t k = 0; k < kMacSchedule.size(); ++k)
    if (ram[kMacSchedule[k].w] != 0) ops.push_back(uint8_t(k));
  return ops;
}

/// α, β, γ from the products `ops` lists only.
template <class Real>
Abg<Real> form_abg(const Latches<Real>& l, const CoefRam<Real>& ram, const MacOps& ops) {
  Real acc[3] = {0, 0, 0};
  for (uint8_t k : ops) acc[kMacSchedule[k].sum] += mac_product(kMacSchedule[k], l, ram);
  return {acc[kAlpha], acc[kBeta], acc[kGamma]};
}

namespace detail {
constexpr bool is_cross(const MacOp& op) { return op.w == kRamD || op.w == kRamE || op.w == kRamF; }

struct OpList {
  std::array<uint8_t, kMacProducts> k{};
  size_t n = 0;
};

constexpr OpList schedule_subset(bool cross_terms) {
  OpList l;
  for (size_t k = 0; k < kMacProducts; ++k)
    if (cross_terms || !is_cross(kMacSchedule[k])) l.k[l.n++] = uint8_t(k);
  return l;
}
inline constexpr OpList kAllOps = schedule_subset(true);
inline constexpr OpList kNoCrossOps = schedule_subset(false);

template <const OpList& Ops, class Real, size_t... I>
Abg<Real> form_abg_unrolled(const Latches<Real>& l, const CoefRam<Real>& ram,
                            std::index_sequence<I...>) {
  Real acc[3] = {0, 0, 0};
  ((acc[kMacSchedule[Ops.k[I]].sum] += mac_product(kMacSchedule[Ops.k[I]], l, ram)),
   ...);  // left to right
  return {acc[kAlpha], acc[kBeta], acc[kGamma]};
}
}  // namespace detail

/// A per-primitive schedule as a mask over kMacSchedule (bit k: product k runs).
using MacMask = uint32_t;
constexpr MacMask kAllProducts = (MacMask(1) << kMacProducts) - 1;

template <class Real>
MacMask sparse_mask(const CoefRam<Real>& ram) {
  MacMask m = 0;
  for (uint8_t k : sparse_ops(ram)) m |= MacMask(1) << k;
  return m;
}

namespace detail {
template <class Real, size_t... K>
Abg<Real> form_abg_masked(const Latches<Real>& l, const CoefRam<Real>& ram, MacMask mask,
                          std::index_sequence<K...>) {
  Real acc[3] = {0, 0, 0};
  // Left to right, in schedule order; a product not in the mask leaves its sum alone.
  ((acc[kMacSchedule[K].sum] = (mask >> K & 1)
                                   ? acc[kMacSchedule[K].sum] + mac_product(kMacSchedule[K], l, ram)
                                   : acc[kMacSchedule[K].sum]),
   ...);
  return {acc[kAlpha], acc[kBeta], acc[kGamma]};
}
}  // namespace detail

/// α, β, γ from the products in `mask`, in schedule order: the same bits as form_abg with that
/// schedule (all products: the full one), unrolled at compile time so the sums stay in registers.
template <class Real>
Abg<Real> form_abg(const Latches<Real>& l, const CoefRam<Real>& ram, MacMask mask) {
  return detail::form_abg_masked(l, ram, mask, std::make_index_sequence<kMacProducts>{});
}

/// The same α, β, γ as form_abg, bit for bit, for the reference renderer: the schedule unrolled at
/// compile time with the accumulators in registers instead of an indexed array (whose
/// store-to-load chain dominated the profiles), and, for a quadric without cross terms
/// (D = E = F = 0: spheres, planes, axis-aligned shapes), without those 12 products — each is ±0,
/// which never changes a sum (the argument of sparse_ops). The same sums as any sparse schedule.
template <class Real>
Abg<Real> form_abg_fast(const Latches<Real>& l, const CoefRam<Real>& ram) {
  using namespace detail;
  if (ram[kRamD] == 0 && ram[kRamE] == 0 && ram[kRamF] == 0)
    return form_abg_unrolled<kNoCrossOps>(l, ram, std::make_index_sequence<kNoCrossOps.n>{});
  return form_abg_unrolled<kAllOps>(l, ram, std::make_index_sequence<kAllOps.n>{});
}

}  // namespace rtm
