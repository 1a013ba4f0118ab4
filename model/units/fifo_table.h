// Every FIFO of a PE, once: its name, what it carries, its depth's configuration key, and which
// units write and read it. The modules (machine/modular_pe.cpp) build their channels from it, the
// PE engine its queues, statistics and deadlock reports list FIFOs in its order, and the units
// name their outputs by it. A build may add FIFOs (units/extra_units.h).
#pragma once

#include <array>
#include <cstddef>
#include <initializer_list>
#include <vector>

#include "config/config.h"
#include "units/unit_kind.h"

namespace rtm {

// clang-format off
enum class FifoId : uint8_t {
  Search,
  Intersect,
  Shade,
  FeedbackSearch,
  FeedbackIntersect,
  Spawn,
  Root,
  RTM_EXTRA_FIFO_IDS  // a build's (units/extra_units.h)
  Ends
};
// clang-format on
constexpr size_t kFifoCount = size_t(FifoId::Ends) + 1;

/// The kind that writes the intersect FIFO, and the FIFO the search units send a ray to for
/// intersection: the search units and the intersect FIFO, unless a build puts a unit between
/// them (units/extra_units.h).
constexpr UnitKind kIntersectWriter = RTM_INTERSECT_WRITER;
constexpr FifoId kSearchToIntersect = RTM_SEARCH_TO_INTERSECT;

/// What travels in a FIFO: a ray (MachineRay), a MAC result (MacResult), or a ray's end (RayEnd).
enum class Payload : uint8_t { Ray, MacResult, End };

struct FifoSpec {
  FifoId id;
  const char* name;  ///< the channel's name in the hierarchy, statistics and waveforms
  const char* kind;  ///< statistics group FIFOs of one kind over all PEs (both feedback paths are
                     ///< "feedback")
  Payload payload;
  const char* depth_key;  ///< the configuration key of its depth
  int MachineConfig::*depth;
  std::vector<UnitKind> writers, readers;
  bool per_lane;    ///< one per intersection unit (inside it), else one per PE
  bool spawn_path;  ///< left out when the scene spawns no rays (PeUnits::spawn_path)
  /// Into the front buffer: whether what arrives returns a credit (a ray fed back, a ray's end)
  /// or is new (a spawned ray: its parent's credit came back with the parent's end).
  bool returns_credit;
  const char* doc;
};

/// In the order statistics and reports list them.
const std::array<FifoSpec, kFifoCount>& fifo_table();
inline const FifoSpec& fifo_spec(FifoId id) { return fifo_table()[size_t(id)]; }

}  // namespace rtm
