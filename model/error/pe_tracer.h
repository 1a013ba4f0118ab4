// A PE's units driven one ray at a time, untimed: the search unit, the MAC and root unit and the
// shading unit do to each ray exactly what they do in the machine (the same unit code, the same
// configuration), without FIFOs, clocks or local memory. Which rays a PE traces and what they
// add to their pixel do not depend on when the units take them (the pixel's sum is
// order-independent, render/pixel_sum.h), so a pixel's tree traced here sums to the machine's
// pixel exactly: the error attribution checks that it does.
#pragma once

#include "config/config.h"
#include "render/ray_result.h"
#include "units/intersection.h"
#include "units/pe_state.h"
#include "units/search_unit.h"
#include "units/shading_unit.h"

namespace rtm {

class PeTracer : public RayTracer {
 public:
  PeTracer(const Scene& s, const Grid& g, const MachineConfig& c);  ///< s and g must outlive it
  void trace(const Ray& ray, RayResult& out) override;
  /// The walks' and tests' counts of every ray traced so far, as the machine's units count them
  /// (rays are counted where the machine spawns them, which this does not: see TreeWork).
  const TraceCounts& counts() const { return pe_.counters.counts; }

 private:
  PeState pe_;
  SearchUnit search_;
  MacUnit mac_;
  RootUnit root_;
  ShadingUnit shading_;
  MacResult job_;
};

}  // namespace rtm
