// What a machine costs: each kind of unit's inventory (the datapath elements, registers, FIFOs
// and SRAMs it is built of), hence its area; its actions in a frame, hence its dynamic energy;
// leakage over the frame's time; each PE's local memory as DRAM, reported apart. What each unit
// is built of and what it does per action is declared once, in unit_build() (unit_cost.cpp), one
// entry per kind of the unit table (units/unit_table.h). Plain C++: no SystemC. docs/cost.md.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cost/technology.h"
#include "config/config.h"
#include "units/pe_state.h"
#include "units/unit_table.h"

namespace rtm {

/// A datapath element of the technology table.
enum class Op : uint8_t { IntAdd, IntCompare, FpAdd, FpMul, FpCompare, FpDiv, FpSqrt };
constexpr size_t kOps = 7;
const char* op_name(Op o);

/// How many of each element, by precision (integer elements are counted under fp32).
struct Elements {
  std::array<std::array<uint64_t, 2>, kOps> n{};
  void add(Op o, Precision p, uint64_t count) { n[size_t(o)][p == Precision::Fp64] += count; }
  uint64_t of(Op o, Precision p) const { return n[size_t(o)][p == Precision::Fp64]; }
  Elements& operator+=(const Elements& e);
  /// The same elements, `times` over.
  Elements times(uint64_t k) const;
};
double area_um2(const Elements& e, const Technology& t);
/// Each element counted once is one operation of it.
double energy_pj(const Elements& e, const Technology& t);

struct Sram {
  std::string name;
  double bytes = 0;
  double word_bits = 0;
};

/// What all of one PE's units of one kind are built of.
struct UnitInventory {
  UnitKind kind = UnitKind::FrontBuffer;
  int units = 0;
  Elements elements;
  uint64_t register_bits = 0;  ///< latches and state
  uint64_t fifo_bits = 0;      ///< the FIFOs it reads: depth x record width
  std::vector<Sram> srams;
  double logic_um2 = 0;  ///< elements, registers and FIFOs
  double sram_um2 = 0;
};

/// The bits of one record of a FIFO's payload (units/fifo_table.h).
uint64_t record_bits(Payload p, const MachineConfig& c);

/// What a PE's units of kind k are built of, for a scene of `primitives` (the coefficient RAM
/// holds every primitive's unless mac_ram_primitives bounds it) with the optional units `units`
/// (what leave_out kept: units/pe_state.h).
UnitInventory unit_inventory(UnitKind k, const MachineConfig& c, const PeUnits& units,
                             uint64_t primitives, const Technology& t);

/// What a frame did, over all PEs: the counters the cost reads (frame/frame_cost.h fills it).
struct FrameActivity {
  int pes = 1;
  double seconds = 0;  ///< the frame's simulated time
  uint64_t pixels = 0;
  uint64_t rays = 0;
  uint64_t voxel_steps = 0, intersection_tests = 0, clip_tests = 0;
  uint64_t mac_products =
      0;  ///< in the intersection precision; skipped (sparse) products are not here
  std::array<uint64_t, kUnitKinds> items{};  ///< each kind's items taken (units/pipeline.h)
  /// Records written into each FIFO of the table (units/fifo_table.h), summed over its copies.
  std::array<uint64_t, kFifoCount> fifo_writes{};
  uint64_t coef_ram_fills = 0;  ///< coefficient records loaded on misses
  uint64_t cache_accesses = 0, cache_line_fills = 0;
  uint64_t memory_bytes = 0;  ///< local-memory bytes moved by every requester, host writes included
  uint64_t link_bytes = 0;    ///< over every link of the interconnect
  /// voxelisation = pe: the primitives each PE placed in its grid and the references it
  /// registered, summed over the PEs.
  uint64_t voxel_primitives = 0, voxel_references = 0;
};

struct UnitCost {
  UnitInventory inventory;
  double dynamic_pj = 0;  ///< over all PEs
};

struct MachineCost {
  std::string technology;
  std::vector<UnitCost> units;               ///< in unit-table order
  double pe_logic_mm2 = 0, pe_sram_mm2 = 0;  ///< one PE
  double interconnect_mm2 = 0;               ///< no technology entry prices the link's area: 0
  double logic_mm2 = 0, sram_mm2 = 0;        ///< all PEs: on-chip
  double memory_mm2 = 0;                     ///< all PEs' local memory as DRAM, apart from the chip
  double memory_capacity_bytes = 0;          ///< per PE
  double memory_dynamic_pj = 0, link_dynamic_pj = 0;
  /// Of the search units' dynamic energy: the PEs building their voxel data (voxelisation = pe).
  double voxelisation_dynamic_pj = 0;
  double dynamic_pj = 0;     ///< units, local memory and link
  double leakage_pj = 0;     ///< on-chip logic and SRAM over the frame
  double energy_pj = 0;      ///< dynamic and leakage
  double frame_seconds = 0;  ///< FrameActivity::seconds
  double power_w = 0;        ///< energy over the frame's time
  double energy_per_ray_pj = 0, energy_per_pixel_pj = 0;

  double area_mm2() const { return logic_mm2 + sram_mm2 + interconnect_mm2; }
};

/// Energy of kind k's units over the frame: each action's elements, register and FIFO writes and
/// SRAM accesses (unit_cost.cpp says what an action is per kind).
double unit_dynamic_pj(UnitKind k, const MachineConfig& c, const PeUnits& units,
                       uint64_t primitives, const FrameActivity& a, const Technology& t);

/// The PEs' build of their voxel data (voxelisation = pe), the search units' 3DDDA steppers', an
/// assumption (docs/cost.md): a
/// primitive's bounds into voxel indices, 6 multiplies and 6 adds in the 3DDDA's precision; a
/// reference, 3 integer adds and 3 compares stepping the indices over those bounds. The bytes it
/// writes are counted in the local memory's.
double voxelisation_dynamic_pj(const MachineConfig& c, const FrameActivity& a, const Technology& t);

MachineCost machine_cost(const MachineConfig& c, const PeUnits& units, uint64_t primitives,
                         const FrameActivity& a, const Technology& t);

}  // namespace rtm
