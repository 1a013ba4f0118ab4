#include "cost/unit_cost.h"

#include <cmath>

#include <gtest/gtest.h>

#include "memory/memory_layout.h"

namespace rtm {
namespace {

const Technology& tech() {
  static const Technology t = load_technology(kBuiltInTechnology);
  return t;
}

MachineCost cost_of(const MachineConfig& c, const PeUnits& u = {}, const FrameActivity& a = {}) {
  FrameActivity act = a;
  act.pes = c.pes;
  return machine_cost(c, u, 100, act, tech());
}

TEST(UnitCost, AreaIsLinearInThePeCount) {
  MachineConfig c;
  const MachineCost one = cost_of(c);
  ASSERT_GT(one.logic_mm2, 0);
  ASSERT_GT(one.sram_mm2, 0);
  for (int pes : {2, 7, 64}) {
    c.pes = pes;
    const MachineCost m = cost_of(c);
    EXPECT_DOUBLE_EQ(m.logic_mm2, pes * one.logic_mm2);
    EXPECT_DOUBLE_EQ(m.sram_mm2, pes * one.sram_mm2);
    EXPECT_DOUBLE_EQ(m.memory_mm2, pes * one.memory_mm2);
    EXPECT_DOUBLE_EQ(m.pe_logic_mm2, one.pe_logic_mm2);
  }
}

TEST(UnitCost, ADynamicPartitionAddsTheTileRequestAndDescriptorToTheFrontBuffer) {
  MachineConfig fixed, dynamic;
  dynamic.partition = Partition::Dynamic;
  const UnitInventory a = unit_inventory(UnitKind::FrontBuffer, fixed, {}, 100, tech()),
                      b = unit_inventory(UnitKind::FrontBuffer, dynamic, {}, 100, tech());
  EXPECT_EQ(b.register_bits - a.register_bits, (kTileRequestBytes + kTileDescriptorBytes) * 8);
  EXPECT_GT(b.logic_um2, a.logic_um2);
  for (const UnitSpec& s : unit_table()) {
    if (s.kind == UnitKind::FrontBuffer) continue;
    EXPECT_EQ(unit_inventory(s.kind, dynamic, {}, 100, tech()).register_bits,
              unit_inventory(s.kind, fixed, {}, 100, tech()).register_bits);
  }
}

TEST(UnitCost, TheMemoryIsItsCapacityInDramBitsApartFromLogic) {
  MachineConfig c;
  const MachineCost m = cost_of(c);
  EXPECT_DOUBLE_EQ(m.memory_mm2,
                   double(c.local_memory_bytes) * 8 * tech().dram_bit_um2.value * 1e-6);
  EXPECT_DOUBLE_EQ(m.area_mm2(), m.logic_mm2 + m.sram_mm2 + m.interconnect_mm2);
}

TEST(UnitCost, Fp64UnitsCostMoreThanFp32) {
  MachineConfig f32, f64;
  f64.precision = Precision::Fp64;
  for (const UnitSpec& s : unit_table()) {
    const UnitInventory a = unit_inventory(s.kind, f32, {}, 100, tech()),
                        b = unit_inventory(s.kind, f64, {}, 100, tech());
    if (s.kind == UnitKind::FrontBuffer) {
      EXPECT_DOUBLE_EQ(b.logic_um2, a.logic_um2)
          << "the front buffer has no floating-point arithmetic";
      continue;
    }
    EXPECT_GT(b.logic_um2, a.logic_um2) << s.name;
  }
  EXPECT_GT(cost_of(f64).logic_mm2, cost_of(f32).logic_mm2);
  // One unit's own key moves only that unit.
  MachineConfig mac64 = f32;
  mac64.intersection_precision = MachineConfig::UnitPrecision::Fp64;
  EXPECT_GT(unit_inventory(UnitKind::Mac, mac64, {}, 100, tech()).sram_um2,
            unit_inventory(UnitKind::Mac, f32, {}, 100, tech()).sram_um2);
  EXPECT_DOUBLE_EQ(unit_inventory(UnitKind::Search, mac64, {}, 100, tech()).logic_um2,
                   unit_inventory(UnitKind::Search, f32, {}, 100, tech()).logic_um2);
}

TEST(UnitCost, ALeftOutUnitCostsNothing) {
  const MachineConfig c;
  PeUnits none;
  none.spawn_path = none.shadow_rays = none.reflection = none.refraction = false;
  const UnitInventory all = unit_inventory(UnitKind::Shading, c, {}, 100, tech());
  const UnitInventory bare = unit_inventory(UnitKind::Shading, c, none, 100, tech());
  EXPECT_LT(bare.logic_um2, all.logic_um2);
  // Each generator's elements are gone, and nothing else.
  for (PeUnits one : {PeUnits{true, false, true, true}, PeUnits{true, true, false, true},
                      PeUnits{true, true, true, false}})
    EXPECT_LT(unit_inventory(UnitKind::Shading, c, one, 100, tech()).logic_um2, all.logic_um2);
  EXPECT_EQ(bare.register_bits, all.register_bits);
  // The spawn FIFO left out takes its bits from the front buffer, its reader.
  const UnitInventory fb = unit_inventory(UnitKind::FrontBuffer, c, {}, 100, tech());
  const UnitInventory fb_bare = unit_inventory(UnitKind::FrontBuffer, c, none, 100, tech());
  const FifoSpec& spawn = fifo_spec(FifoId::Spawn);
  EXPECT_EQ(fb.fifo_bits - fb_bare.fifo_bits,
            uint64_t(c.*spawn.depth) * record_bits(spawn.payload, c));
  EXPECT_DOUBLE_EQ(fb.logic_um2 - fb_bare.logic_um2, double(c.*spawn.depth) *
                                                         double(record_bits(spawn.payload, c)) *
                                                         tech().register_bit_um2.value);
}

TEST(UnitCost, TheCoefficientRamHoldsEveryPrimitiveUnlessBounded) {
  MachineConfig c;
  c.intersection_units = 2;
  const UnitInventory all = unit_inventory(UnitKind::Mac, c, {}, 1000, tech());
  ASSERT_EQ(all.srams.size(), 2u);
  EXPECT_DOUBLE_EQ(all.srams[0].bytes, 1000.0 * kRamWords * 4);
  c.mac_ram_primitives = 10;
  EXPECT_DOUBLE_EQ(unit_inventory(UnitKind::Mac, c, {}, 1000, tech()).srams[0].bytes,
                   10.0 * kRamWords * 4);
  EXPECT_TRUE(unit_inventory(UnitKind::Search, c, {}, 1000, tech()).srams.empty());
  c.voxel_cache_bytes = 4096;
  const UnitInventory s = unit_inventory(UnitKind::Search, c, {}, 1000, tech());
  ASSERT_EQ(s.srams.size(), 1u);
  EXPECT_DOUBLE_EQ(s.sram_um2, 4096.0 * 8 * tech().sram_bit_um2.value);
}

TEST(UnitCost, AnIdleMachineCostsOnlyLeakage) {
  MachineConfig c;
  FrameActivity a;
  a.seconds = 1e-3;
  const MachineCost m = cost_of(c, {}, a);
  EXPECT_EQ(m.dynamic_pj, 0);
  for (const UnitCost& u : m.units) EXPECT_EQ(u.dynamic_pj, 0) << unit_name(u.inventory.kind);
  double sram_bits = 0;
  for (const UnitCost& u : m.units)
    for (const Sram& s : u.inventory.srams) sram_bits += s.bytes * 8;
  const double leak_w =
      m.logic_mm2 * 1e6 * 50e-9 + sram_bits * 1000e-12;  // the 45 nm file's leakage
  EXPECT_NEAR(m.leakage_pj, leak_w * 1e-3 * 1e12, 1e-9 * m.leakage_pj);
  EXPECT_DOUBLE_EQ(m.energy_pj, m.leakage_pj);
  EXPECT_NEAR(m.power_w, leak_w, 1e-12 * leak_w);
}

}  // namespace
}  // namespace rtm

namespace rtm {
namespace {

// A tiny frame's energy worked out by hand from its counts and the 45 nm table, written out
// here apart from unit_cost.cpp's tables: 10 voxel steps of 2 walks, 3 tests of 7 products,
// 2 FIFO writes of rays into the search FIFO, 64 bytes of local memory, 100 link bytes.
TEST(UnitCost, ATinyFramesEnergyByHand) {
  MachineConfig c;  // fp32 throughout
  PeUnits none;
  none.spawn_path = none.shadow_rays = none.reflection = none.refraction = false;
  FrameActivity a;
  a.rays = 2;
  a.voxel_steps = 10;
  a.intersection_tests = 3;
  a.mac_products = 21;
  a.fifo_writes[size_t(FifoId::Search)] = 2;
  a.memory_bytes = 64;
  a.link_bytes = 100;
  const MachineCost m = machine_cost(c, none, 5, a, tech());

  const double reg = 0.01, ray = 60 * 8 + 64;  // a register bit written; a ray's bits
  // Search: per step 2 fp compares 0.1, an fp add 0.9, an int add 0.1, 2 int compares 0.1, the
  // walk's 3 x 32 + 6 x 32 bits; per walk 3 divides 20.3, 3 mul 3.7, 3 add 0.9, the walk's bits;
  // the search FIFO's writes.
  const double walk = 288 * reg;
  const double search = 10 * (2 * 0.1 + 0.9 + 0.1 + 2 * 0.1 + walk) +
                        2 * (3 * 20.3 + 3 * 3.7 + 3 * 0.9 + walk) + 2 * ray * reg;
  // MAC: per product 3.7 + 0.9, its accumulator's 32 bits and a word of a 5 x 13 x 4 byte RAM
  // (Horowitz's 8 KB 64-bit read, 10 pJ, halved for 32 bits, times the capacity's square root).
  const double ram = 10 * 0.5 * std::sqrt(5 * 13 * 4 / 8192.0);
  const double mac = 21 * (3.7 + 0.9 + 32 * reg + ram);
  // Root: per test 4 mul, 3 add, a root 27.7, a divide 20.3, 2 compares, 4 words latched.
  const double root = 3 * (4 * 3.7 + 3 * 0.9 + 27.7 + 20.3 + 2 * 0.1 + 128 * reg);
  const double memory = 64 * 8 * 30.5, link = 100 * 8 * 10.0;

  EXPECT_NEAR(m.units[size_t(UnitKind::Search)].dynamic_pj, search, 1e-9);
  EXPECT_NEAR(m.units[size_t(UnitKind::Mac)].dynamic_pj, mac, 1e-9);
  EXPECT_NEAR(m.units[size_t(UnitKind::Root)].dynamic_pj, root, 1e-9);
  EXPECT_EQ(m.units[size_t(UnitKind::FrontBuffer)].dynamic_pj, 0);
  EXPECT_EQ(m.units[size_t(UnitKind::Shading)].dynamic_pj, 0);
  EXPECT_NEAR(m.memory_dynamic_pj, memory, 1e-9);
  EXPECT_NEAR(m.link_dynamic_pj, link, 1e-9);
  EXPECT_NEAR(m.dynamic_pj, search + mac + root + memory + link, 1e-6);
  EXPECT_EQ(m.leakage_pj, 0) << "no time passed";
  EXPECT_NEAR(m.energy_per_ray_pj, m.energy_pj / 2, 1e-9);
}

TEST(UnitCost, AMacProductIsTheTablesMultiplyPlusAddInItsPrecision) {
  for (Precision p : {Precision::Fp32, Precision::Fp64}) {
    MachineConfig c;
    c.precision = p;
    c.mac_ram_primitives = 1;
    FrameActivity one, none;
    one.mac_products = 1;
    const double e = unit_dynamic_pj(UnitKind::Mac, c, {}, 1, one, tech()) -
                     unit_dynamic_pj(UnitKind::Mac, c, {}, 1, none, tech());
    const double w = p == Precision::Fp64 ? 64 : 32;
    const double ram = sram_access_energy_pj(tech(), 13 * w / 8, w);
    EXPECT_NEAR(e - ram - w * tech().register_bit_write_pj.value, mac_product_energy_pj(tech(), p),
                1e-12);
  }
  EXPECT_DOUBLE_EQ(mac_product_energy_pj(tech(), Precision::Fp32), 3.7 + 0.9);
}

}  // namespace
}  // namespace rtm
