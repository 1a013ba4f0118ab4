// The kinds of unit in a PE, in their same-cycle rank: within a PE, units due in the same cycle
// act in this order (arbitration = ranked, machine/timekeeper.h), units of one kind in the order
// they took their work, so which of the replicated search units holds a ray never matters. Root
// units rank by their lane (Root + lane): each takes only its own MAC's results, so no work order
// could rank them. The modules and the PE engine both follow it.
#pragma once

#include <cstdint>

namespace rtm {

enum class UnitKind : uint8_t { FrontBuffer, Shading, Search, Mac, Root };

/// The unit's name in the object hierarchy, waveforms and the event log (with its number for
/// replicated units: search0, mac1, ...).
inline const char* unit_name(UnitKind k) {
  switch (k) {
    case UnitKind::FrontBuffer: return "front_buffer";
    case UnitKind::Shading: return "shading";
    case UnitKind::Search: return "search";
    case UnitKind::Mac: return "mac";
    case UnitKind::Root: return "root";
  }
  return "?";
}

}  // namespace rtm
