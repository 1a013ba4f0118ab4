// The kinds whose units take a ray from their one input FIFO and write it, worked on, to the
// FIFO their Work's Output names: the search units, and any kind a build adds as one
// (units/extra_units.h). Both schedulers run every such kind with one set of operations (the
// PE engine's and machine/ray_stage_module.h), so such a kind needs none of its own: its class
// (a constructor (PeState&, int index) and Work take(MachineRay&, uint64_t now)), its rows and its
// FIFOs' rows are all it adds.
#pragma once

#include <type_traits>

#include "units/extra_units.h"
#include "units/search_unit.h"
#include "units/unit_kind.h"
#ifdef RTM_EXTRA_UNIT_CLASSES
#include RTM_EXTRA_UNIT_CLASSES
#endif

namespace rtm {

/// Every ray stage as X(kind, class), in rank order: the search units, then any a build adds. A
/// new one is an entry here, and both schedulers run it.
#define RTM_RAY_STAGES(X) X(Search, SearchUnit) RTM_EXTRA_RAY_STAGES(X)

/// value: whether kind K is a ray stage; Unit: its class.
template <UnitKind K>
struct RayStage : std::false_type {};

#define RTM_RAY_STAGE(kind, Class)                   \
  template <>                                        \
  struct RayStage<UnitKind::kind> : std::true_type { \
    using Unit = Class;                              \
  };
RTM_RAY_STAGES(RTM_RAY_STAGE)
#undef RTM_RAY_STAGE

/// Calls f(std::integral_constant<UnitKind, K>) for each ray stage K, in rank order.
template <class F>
void for_each_ray_stage(F&& f) {
#define RTM_RAY_STAGE(kind, Class) f(std::integral_constant<UnitKind, UnitKind::kind>{});
  RTM_RAY_STAGES(RTM_RAY_STAGE)
#undef RTM_RAY_STAGE
}

}  // namespace rtm
