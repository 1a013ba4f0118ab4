// The kinds of unit in a PE, in their same-cycle rank: within a PE, units due in the same cycle
// act in this order (arbitration = ranked, machine/timekeeper.h), units of one kind in the order
// they took their work, so which of the replicated search units holds a ray never matters. Root
// units rank by their lane (Root + lane): each takes only its own MAC's results, so no work order
// could rank them. The modules and the PE engine both follow it. What each kind is, is the unit
// table's (units/unit_table.h). A build may add kinds (units/extra_units.h).
#pragma once

#include <cstddef>
#include <cstdint>

#include "units/extra_units.h"

namespace rtm {

// clang-format off
enum class UnitKind : uint8_t {
  FrontBuffer,
  Shading,
  Search,
  RTM_EXTRA_UNIT_KINDS  // a build's (units/extra_units.h)
  Mac,
  Root
};
// clang-format on
constexpr size_t kUnitKinds = size_t(UnitKind::Root) + 1;

}  // namespace rtm
