// An intersection unit (paper §5): the MAC forms α, β, γ for every primitive in the examined
// voxel; the root unit solves each quadratic, clip tests keep the bounded part, and the sort keeps
// the nearest hit inside the voxel. The paper has one; with several (intersection_units), the
// lane dispatcher (units/lane_dispatcher.h) hands each ray to the lowest-numbered idle one.
#pragma once

#include <ostream>
#include <vector>

#include "units/lane_dispatcher.h"
#include "units/mac_timing.h"
#include "units/output.h"
#include "units/routing.h"

namespace rtm {

/// What the MAC hands the root unit: the ray and α, β, γ per primitive of its voxel.
struct MacResult {
  MachineRay r;
  MacTiming::Job plan;  ///< when each primitive's sums left the MAC
  std::vector<Abg<float>> abg32;
  std::vector<Abg<double>> abg64;
};
inline std::ostream& operator<<(std::ostream& os, const MacResult& m) { return os << m.r; }

class MacUnit {
 public:
  MacUnit(PeState& pe, int lane) : pe_(pe), lane_(lane), timing_(pe.config) {}

  /// The job for m.r's examined voxel, taken at `now`: fills m's sums and plan, counts products.
  Work take(MacResult& m, uint64_t now);
  const MacTiming& timing() const { return timing_; }
  int lane() const { return lane_; }

 private:
  PeState& pe_;
  int lane_;
  MacTiming timing_;
};

/// Cycles the root unit, clip tests and sort need after the MAC finished a voxel, given each
/// primitive's clip-test count: primitive p's roots are out root_latency after its sums, and its
/// clip tests and sort then run on one shared unit.
uint64_t back_end_cycles(const MachineConfig& c, const MacTiming::Job& mac,
                         const std::vector<uint32_t>& clips);

class RootUnit {
 public:
  RootUnit(PeState& pe, int lane) : pe_(pe), lane_(lane) {}

  /// The roots, clips and sort for a MAC result taken at `now`; routes m.r (§5.1).
  Work take(MacResult& m, uint64_t now);
  int lane() const { return lane_; }

 private:
  PeState& pe_;
  int lane_;
  std::vector<uint32_t> clips_;
};

}  // namespace rtm
