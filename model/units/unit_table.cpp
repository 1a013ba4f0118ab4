#include "units/unit_table.h"

#include <algorithm>
#include <stdexcept>

#include "geom/mac_schedule.h"

namespace rtm {

namespace {

using M = MachineConfig;
using U = UnitKind;

// Each unit's longest item; their sum bounds a ray's pass round the loop.
uint64_t front_item(const M& c, const ItemBounds& b) {
  return uint64_t(c.fb_dispatch_cycles) + uint64_t(c.pe_ray_cycles) +
         b.access;  // a spilled ray read back
}
uint64_t shading_item(const M& c, const ItemBounds& b) {
  return uint64_t(c.shade_cycles) +
         uint64_t(c.spawn_cycles + c.accumulate_cycles) * (b.lights + 3) + b.access;
}
uint64_t search_item(const M& c, const ItemBounds& b) {
  return b.walk_voxels *
         (uint64_t(c.dda_step_cycles) + b.access);  // search_walk = until_occupied: the whole walk
}
uint64_t mac_item(const M& c, const ItemBounds& b) {
  const uint64_t test = uint64_t(kMacProducts) * uint64_t(c.add_latency) +
                        2 * uint64_t(c.mul_latency) + uint64_t(c.add_latency);
  return (b.fullest_voxel + 1) * (test + b.access);
}
uint64_t root_item(const M& c, const ItemBounds& b) {
  const uint64_t test = uint64_t(c.root_cycles()) + uint64_t(c.sort_cycles) +
                        uint64_t(c.clip_cycles) * (b.most_clips + 1);
  return (b.fullest_voxel + 1) * test + b.access;
}

}  // namespace

const std::array<UnitSpec, kUnitKinds>& unit_table() {
  static const std::array<UnitSpec, kUnitKinds> table = {{
      {U::FrontBuffer, "front_buffer", "front buffer", nullptr, nullptr, false, false, true,
       front_item,
       "admits primary rays, merges the rays fed back and spawned, hands them to the search units "
       "(§4.2)"},
      {U::Shading, "shading", "shading", nullptr, nullptr, false, false, true, shading_item,
       "adds brightness into the frame buffer, spawns shadow and branch rays (§6)"},
      {U::Search, "search", "search", "search_units", &M::search_units, false, false, true,
       search_item, "a 3DDDA pass over the ray's voxel, routed by its occupancy (§4)"},
      // clang-format off
      RTM_EXTRA_UNIT_ROWS  // a build's (units/extra_units.h)
      {U::Mac, "mac", "MAC", "intersection_units", &M::intersection_units, false, true, true,
       mac_item, "alpha, beta, gamma for every primitive in the voxel (§5.2)"},
      // clang-format on
      {U::Root, "root", "root/sort", "intersection_units", &M::intersection_units, true, true, true,
       root_item, "roots, clip tests and the nearest hit in the voxel (§5.1)"},
  }};
  return table;
}

namespace {
std::vector<FifoId> fifos(UnitKind k, std::vector<UnitKind> FifoSpec::*side) {
  std::vector<FifoId> out;
  for (const FifoSpec& f : fifo_table())
    if (std::count((f.*side).begin(), (f.*side).end(), k)) out.push_back(f.id);
  return out;
}
}  // namespace

std::vector<UnitKind> pipeline_order() {
  std::vector<UnitKind> order;
  std::array<bool, kUnitKinds> placed{};
  // Whether every kind that writes a FIFO k reads (besides k itself) is placed.
  auto ready = [&](UnitKind k) {
    for (const FifoSpec& f : fifo_table()) {
      const bool back = std::count(f.readers.begin(), f.readers.end(), UnitKind::FrontBuffer);
      if (back || !std::count(f.readers.begin(), f.readers.end(), k)) continue;
      for (UnitKind w : f.writers)
        if (w != k && !placed[size_t(w)]) return false;
    }
    return true;
  };
  while (order.size() < kUnitKinds) {
    const auto next =
        std::find_if(unit_table().begin(), unit_table().end(),
                     [&](const UnitSpec& u) { return !placed[size_t(u.kind)] && ready(u.kind); });
    if (next == unit_table().end())
      throw std::logic_error("the FIFO table's units feed one another in a loop");
    placed[size_t(next->kind)] = true;
    order.push_back(next->kind);
  }
  return order;
}

std::vector<FifoId> inputs(UnitKind k) { return fifos(k, &FifoSpec::readers); }
std::vector<FifoId> outputs(UnitKind k) { return fifos(k, &FifoSpec::writers); }

int fifo_count(const FifoSpec& f, const MachineConfig& c) {
  return f.per_lane ? unit_count(f.writers.front(), c) : 1;
}

}  // namespace rtm
