#include "cost/unit_cost.h"

#include <algorithm>
#include <array>

#include "memory/records.h"
#include "memory/voxel_cache.h"
#include "memory/memory_layout.h"

namespace rtm {

namespace {

using U = UnitKind;
using P = Precision;
using A = FrameActivity;

/// One kind of action of a unit and what each one costs: the elements it works once, the register
/// bits it writes, and the SRAM words it reads or writes.
struct Action {
  uint64_t (*count)(const A&);
  Elements ops;
  uint64_t register_bits = 0;
  double sram_words = 0;  ///< in the unit's first SRAM, of its word
};

/// What a PE's units of one kind are built of and what they do: declared once, here.
struct UnitBuild {
  Elements elements;  ///< all of the kind's units
  uint64_t register_bits = 0;
  std::vector<Sram> srams;
  std::vector<Action> actions;
};

uint64_t word_bits(P p) { return p == P::Fp64 ? 64 : 32; }
/// A ray as the spill area keeps it (units/memory_layout.h), with its hit's t and primitive.
uint64_t ray_bits() { return kSpillRecordBytes * 8 + 64; }

Elements ops(std::initializer_list<std::pair<Op, uint64_t>> list, P p) {
  Elements e;
  for (auto [o, n] : list) e.add(o, o == Op::IntAdd || o == Op::IntCompare ? P::Fp32 : p, n);
  return e;
}

// §4.2: the buffer at the head of the pipeline. Its rays sit in an SRAM of front_buffer_capacity
// records; a counter and its limit keep the loop's credits. Each ray dispatched was written into
// the buffer once and is read out once, through the output latch. A dynamic partition's PE asks
// for tiles from here: a request register and a descriptor buffer (one request is out at a time).
UnitBuild front_buffer(const MachineConfig& c, const PeUnits&, uint64_t) {
  UnitBuild b;
  const Elements credit = ops({{Op::IntAdd, 1}, {Op::IntCompare, 1}}, P::Fp32);
  b.elements = credit;
  b.register_bits = ray_bits();
  if (c.partition == Partition::Dynamic)
    b.register_bits += (kTileRequestBytes + kTileDescriptorBytes) * 8;
  b.srams.push_back({"front_buffer", double(c.front_buffer_capacity) * double(ray_bits()) / 8,
                     double(ray_bits())});
  b.actions.push_back(
      {[](const A& a) { return a.items[size_t(U::FrontBuffer)]; }, credit, ray_bits(), 2});
  return b;
}

// §6: brightness into the frame buffer, then shadow and branch rays. The paper gives no datapath;
// these are the operations of the model's shading (render/shade.h): the hit point (3 mul, 3 add),
// the quadric's gradient as normal (9 mul, 9 add), its normalisation (3 mul, 2 add, a root and a
// divide) and the brightness (3 mul, 3 add); each ray generator the leave-out analysis kept adds
// its own. Each item is taken to pass every element once: an upper bound, as a shadow ray
// arriving only adds brightness.
UnitBuild shading(const MachineConfig& c, const PeUnits& u, uint64_t) {
  const P p = c.shading_precision_in_force();
  UnitBuild b;
  Elements e = ops({{Op::FpMul, 18}, {Op::FpAdd, 17}, {Op::FpSqrt, 1}, {Op::FpDiv, 1}}, p);
  if (u.shadow_rays)  // towards each light (3 add), its length (3 mul, 2 add, root, divide),
                      // contribution x kd
    e += ops({{Op::FpAdd, 5}, {Op::FpMul, 6}, {Op::FpSqrt, 1}, {Op::FpDiv, 1}}, p);
  if (u.reflection)  // d - 2(d.n)n (6 mul, 5 add), contribution x ks, the threshold
    e += ops({{Op::FpMul, 9}, {Op::FpAdd, 5}, {Op::FpCompare, 1}}, p);
  if (u.refraction)  // Snell's law (9 mul, 6 add, a root), contribution x kt, the threshold
    e += ops({{Op::FpMul, 12}, {Op::FpAdd, 6}, {Op::FpSqrt, 1}, {Op::FpCompare, 1}}, p);
  b.elements = e;
  b.register_bits = ray_bits() + 3 * word_bits(p);  // the ray and its contribution's colour
  b.actions.push_back({[](const A& a) { return a.items[size_t(U::Shading)]; }, e, b.register_bits});
  return b;
}

// §4: the 3DDDA (Snyder & Barr 1987), replicated (four units in Fig. 1). A step picks the axis
// of the nearest plane crossing (2 compares), advances that crossing (an add) and the voxel
// index (an integer add), and checks the grid's bound and the voxel's occupancy (2 integer
// compares). A walk's set-up divides by the direction (3 divides on one divider) and finds the
// first crossings (3 mul, 3 add). The voxel cache, if any, is the search units'.
UnitBuild search(const MachineConfig& c, const PeUnits&, uint64_t) {
  const P p = c.dda_precision_in_force();
  const uint64_t n = uint64_t(c.search_units);
  UnitBuild b;
  b.elements = ops({{Op::FpCompare, 2},
                    {Op::FpAdd, 1},
                    {Op::FpMul, 1},
                    {Op::FpDiv, 1},
                    {Op::IntAdd, 1},
                    {Op::IntCompare, 2}},
                   p)
                   .times(n);
  // Each unit's walk: the voxel index (3 integers), the next crossings and their steps (6 words).
  const uint64_t walk_bits = 3 * 32 + 6 * word_bits(p);
  b.register_bits = n * (walk_bits + ray_bits());
  const bool cache = c.voxel_cache_bytes > 0;
  if (cache) b.srams.push_back({"voxel_cache", double(c.voxel_cache_bytes), 32});
  b.actions.push_back(
      {[](const A& a) { return a.voxel_steps; },
       ops({{Op::FpCompare, 2}, {Op::FpAdd, 1}, {Op::IntAdd, 1}, {Op::IntCompare, 2}}, p),
       walk_bits});
  b.actions.push_back({[](const A& a) { return a.rays; },
                       ops({{Op::FpDiv, 3}, {Op::FpMul, 3}, {Op::FpAdd, 3}}, p), walk_bits});
  if (cache) {
    const double line_words = double(VoxelCache::from(c).line_bytes()) / 4;
    b.actions.push_back({[](const A& a) { return a.cache_accesses; }, {}, 0, 1});
    b.actions.push_back({[](const A& a) { return a.cache_line_fills; }, {}, 0, line_words});
  }
  return b;
}

// §5.2, Fig. 2: two multipliers and an adder chained, the ray's U and V in latches, the
// coefficients in a RAM (every primitive's unless mac_ram_primitives bounds it; memory/records.h's
// record), one per intersection unit. A product is one multiply and the accumulating add
// (mac_product_energy_pj) and one coefficient word read; multiplier 1's product of two ray
// factors is not counted apart.
UnitBuild mac(const MachineConfig& c, const PeUnits&, uint64_t primitives) {
  const P p = c.intersection_precision_in_force();
  const uint64_t lanes = uint64_t(c.intersection_units);
  UnitBuild b;
  b.elements = ops({{Op::FpMul, 2}, {Op::FpAdd, 1}}, p).times(lanes);
  b.register_bits =
      lanes * (6 + 1 + 2) * word_bits(p);  // U and V, the accumulator, two stage latches
  const double records =
      double(c.mac_ram_primitives > 0 ? uint64_t(c.mac_ram_primitives) : primitives);
  const double ram_bytes = records * double(coef_record_bytes(p));
  for (uint64_t k = 0; k < lanes; ++k)
    b.srams.push_back({"coefficient_ram", ram_bytes, double(word_bits(p))});
  b.actions.push_back({[](const A& a) { return a.mac_products; },
                       ops({{Op::FpMul, 1}, {Op::FpAdd, 1}}, p), word_bits(p), 1});
  b.actions.push_back({[](const A& a) { return a.coef_ram_fills; }, {}, 0, double(kRamWords)});
  b.actions.push_back({[](const A& a) { return a.items[size_t(U::Mac)]; },
                       {},
                       6 * word_bits(p)});  // U, V latched per job
  return b;
}

// §5.1: roots and the nearest hit; the paper does not describe the unit. A test forms the
// discriminant (2 mul, an add), its root, the reciprocal of 2 alpha (a divide), the two roots
// (2 mul, 2 add) and compares them with zero and the nearest so far (2 compares); a clip test
// is a half-space n.p + d (3 mul, 3 add, a compare). One per intersection unit.
UnitBuild root(const MachineConfig& c, const PeUnits&, uint64_t) {
  const P p = c.intersection_precision_in_force();
  const uint64_t lanes = uint64_t(c.intersection_units);
  UnitBuild b;
  b.elements =
      ops({{Op::FpMul, 4}, {Op::FpAdd, 3}, {Op::FpSqrt, 1}, {Op::FpDiv, 1}, {Op::FpCompare, 2}}, p)
          .times(lanes);
  b.register_bits =
      lanes * (4 * word_bits(p) + 32);  // alpha, beta, gamma, the nearest t and its primitive
  b.actions.push_back(
      {[](const A& a) { return a.intersection_tests; },
       ops({{Op::FpMul, 4}, {Op::FpAdd, 3}, {Op::FpSqrt, 1}, {Op::FpDiv, 1}, {Op::FpCompare, 2}},
           p),
       4 * word_bits(p)});
  b.actions.push_back({[](const A& a) { return a.clip_tests; },
                       ops({{Op::FpMul, 3}, {Op::FpAdd, 3}, {Op::FpCompare, 1}}, p)});
  return b;
}

struct BuildOf {
  UnitKind kind;
  UnitBuild (*build)(const MachineConfig&, const PeUnits&, uint64_t);
};

/// Beside the unit table: each kind's build, in its order.
// clang-format off
constexpr std::array<BuildOf, kUnitKinds> kBuilds = {{
    {U::FrontBuffer, front_buffer},
    {U::Shading, shading},
    {U::Search, search},
    RTM_EXTRA_UNIT_BUILDS  // a build's (units/extra_units.h)
    {U::Mac, mac},
    {U::Root, root}}};
// clang-format on
constexpr bool in_kind_order() {
  for (size_t k = 0; k < kUnitKinds; ++k)
    if (kBuilds[k].kind != UnitKind(k)) return false;
  return true;
}
static_assert(in_kind_order(), "kBuilds lists every unit kind once, in UnitKind's order");

UnitBuild build(UnitKind k, const MachineConfig& c, const PeUnits& u, uint64_t primitives) {
  return kBuilds[size_t(k)].build(c, u, primitives);
}

/// An element's energy and area entries in the technology, in fp32 and in fp64 (the integer
/// elements have one of each: the 3DDDA's precision does not widen them).
struct OpEntries {
  TechValue Technology::*pj32;
  TechValue Technology::*pj64;
  TechValue Technology::*um2_32;
  TechValue Technology::*um2_64;
};
using Tech = Technology;
constexpr std::array<OpEntries, kOps> kOpEntries = {{
    {&Tech::int32_add_pj, &Tech::int32_add_pj, &Tech::int32_add_um2, &Tech::int32_add_um2},
    {&Tech::int32_compare_pj, &Tech::int32_compare_pj, &Tech::int32_compare_um2,
     &Tech::int32_compare_um2},
    {&Tech::fp32_add_pj, &Tech::fp64_add_pj, &Tech::fp32_add_um2, &Tech::fp64_add_um2},
    {&Tech::fp32_mul_pj, &Tech::fp64_mul_pj, &Tech::fp32_mul_um2, &Tech::fp64_mul_um2},
    {&Tech::fp32_compare_pj, &Tech::fp64_compare_pj, &Tech::fp32_compare_um2,
     &Tech::fp64_compare_um2},
    {&Tech::fp32_div_pj, &Tech::fp64_div_pj, &Tech::fp32_div_um2, &Tech::fp64_div_um2},
    {&Tech::fp32_sqrt_pj, &Tech::fp64_sqrt_pj, &Tech::fp32_sqrt_um2, &Tech::fp64_sqrt_um2},
}};

double op_pj(Op o, P p, const Technology& t) {
  const OpEntries& e = kOpEntries[size_t(o)];
  return (t.*(p == P::Fp64 ? e.pj64 : e.pj32)).value;
}

double op_um2(Op o, P p, const Technology& t) {
  const OpEntries& e = kOpEntries[size_t(o)];
  return (t.*(p == P::Fp64 ? e.um2_64 : e.um2_32)).value;
}

template <class F>
double sum_over(const Elements& e, F&& f) {
  double s = 0;
  for (size_t o = 0; o < kOps; ++o)
    for (P p : {P::Fp32, P::Fp64}) s += double(e.of(Op(o), p)) * f(Op(o), p);
  return s;
}

/// A FIFO is its reader's input queue: its bits and writes are the reader's.
bool reads(UnitKind k, const FifoSpec& f) { return f.readers.front() == k; }

}  // namespace

const char* op_name(Op o) {
  static const char* const names[kOps] = {"int_add",    "int_compare", "fp_add", "fp_mul",
                                          "fp_compare", "fp_div",      "fp_sqrt"};
  return names[size_t(o)];
}

Elements& Elements::operator+=(const Elements& e) {
  for (size_t o = 0; o < kOps; ++o)
    for (size_t p = 0; p < 2; ++p) n[o][p] += e.n[o][p];
  return *this;
}

Elements Elements::times(uint64_t k) const {
  Elements e = *this;
  for (auto& o : e.n)
    for (uint64_t& x : o) x *= k;
  return e;
}

double area_um2(const Elements& e, const Technology& t) {
  return sum_over(e, [&](Op o, P p) { return op_um2(o, p, t); });
}
double energy_pj(const Elements& e, const Technology& t) {
  return sum_over(e, [&](Op o, P p) { return op_pj(o, p, t); });
}

uint64_t record_bits(Payload p, const MachineConfig& c) {
  switch (p) {
    case Payload::Ray:
      return ray_bits();
    // alpha, beta, gamma of one primitive, its number and the ray's
    case Payload::MacResult:
      return 3 * word_bits(c.intersection_precision_in_force()) + 64;
    case Payload::End:
      return 32;  // the ray's number
  }
  return 0;
}

UnitInventory unit_inventory(UnitKind k, const MachineConfig& c, const PeUnits& units,
                             uint64_t primitives, const Technology& t) {
  const UnitBuild b = build(k, c, units, primitives);
  UnitInventory inv;
  inv.kind = k;
  inv.units = unit_count(k, c);
  inv.elements = b.elements;
  inv.register_bits = b.register_bits;
  for (const FifoSpec& f : fifo_table())
    if (reads(k, f) && units.has(f))
      inv.fifo_bits +=
          uint64_t(fifo_count(f, c)) * uint64_t(c.*f.depth) * record_bits(f.payload, c);
  inv.srams = b.srams;
  inv.logic_um2 = area_um2(inv.elements, t) +
                  double(inv.register_bits + inv.fifo_bits) * t.register_bit_um2.value;
  for (const Sram& s : inv.srams) inv.sram_um2 += sram_area_um2(t, s.bytes);
  return inv;
}

double unit_dynamic_pj(UnitKind k, const MachineConfig& c, const PeUnits& units,
                       uint64_t primitives, const FrameActivity& a, const Technology& t) {
  const UnitBuild b = build(k, c, units, primitives);
  const double reg = t.register_bit_write_pj.value;
  double e = 0;
  for (const Action& x : b.actions) {
    double each = energy_pj(x.ops, t) + double(x.register_bits) * reg;
    if (x.sram_words > 0 && !b.srams.empty())
      each +=
          x.sram_words * sram_access_energy_pj(t, b.srams.front().bytes, b.srams.front().word_bits);
    e += double(x.count(a)) * each;
  }
  for (const FifoSpec& f : fifo_table())
    if (reads(k, f))
      e += double(a.fifo_writes[size_t(f.id)]) * double(record_bits(f.payload, c)) * reg;
  return e;
}

double voxelisation_dynamic_pj(const MachineConfig& c, const FrameActivity& a,
                               const Technology& t) {
  const Precision p = c.dda_precision_in_force();
  Elements primitive, reference;
  primitive.add(Op::FpMul, p, 6);
  primitive.add(Op::FpAdd, p, 6);
  reference.add(Op::IntAdd, Precision::Fp32, 3);
  reference.add(Op::IntCompare, Precision::Fp32, 3);
  return double(a.voxel_primitives) * energy_pj(primitive, t) +
         double(a.voxel_references) * energy_pj(reference, t);
}

MachineCost machine_cost(const MachineConfig& c, const PeUnits& units, uint64_t primitives,
                         const FrameActivity& a, const Technology& t) {
  MachineCost m;
  m.technology = t.name;
  m.voxelisation_dynamic_pj = voxelisation_dynamic_pj(c, a, t);
  double sram_bits = 0;
  for (const UnitSpec& s : unit_table()) {
    UnitCost u{unit_inventory(s.kind, c, units, primitives, t)};
    u.dynamic_pj = unit_dynamic_pj(s.kind, c, units, primitives, a, t);
    // The search units' 3DDDA steppers build the voxel data: theirs.
    if (s.kind == UnitKind::Search) u.dynamic_pj += m.voxelisation_dynamic_pj;
    m.pe_logic_mm2 += u.inventory.logic_um2 * 1e-6;
    m.pe_sram_mm2 += u.inventory.sram_um2 * 1e-6;
    for (const Sram& r : u.inventory.srams) sram_bits += r.bytes * 8;
    m.dynamic_pj += u.dynamic_pj;
    m.units.push_back(std::move(u));
  }
  const double pes = double(a.pes);
  m.logic_mm2 = m.pe_logic_mm2 * pes;
  m.sram_mm2 = m.pe_sram_mm2 * pes;
  m.memory_capacity_bytes = double(c.local_memory_bytes);
  m.memory_mm2 = m.memory_capacity_bytes * 8 * t.dram_bit_um2.value * 1e-6 * pes;
  // Reads and writes are not told apart in the counts: each byte is priced as a read.
  m.memory_dynamic_pj = double(a.memory_bytes) * 8 * t.dram_read_bit_pj.value;
  m.link_dynamic_pj = double(a.link_bytes) * 8 * t.link_bit_pj.value;
  m.dynamic_pj += m.memory_dynamic_pj + m.link_dynamic_pj;
  const double leak_w = m.logic_mm2 * 1e6 * t.logic_leakage_nw_per_um2.value * 1e-9 +
                        sram_bits * pes * t.sram_leakage_pw_per_bit.value * 1e-12;
  m.leakage_pj = leak_w * a.seconds * 1e12;
  m.energy_pj = m.dynamic_pj + m.leakage_pj;
  m.frame_seconds = a.seconds;
  m.power_w = a.seconds > 0 ? m.energy_pj * 1e-12 / a.seconds : 0;
  m.energy_per_ray_pj = a.rays ? m.energy_pj / double(a.rays) : 0;
  m.energy_per_pixel_pj = a.pixels ? m.energy_pj / double(a.pixels) : 0;
  return m;
}

}  // namespace rtm
