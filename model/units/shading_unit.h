// The shading unit (paper §6): adds brightness into the PE's frame buffer and spawns shadow,
// reflected and transmitted rays back into the front buffer. Its outputs go in one order: the
// ray's end first (its credit), then each spawned ray.
#pragma once

#include "render/pixel_sum.h"
#include "render/shade.h"
#include "units/output.h"

namespace rtm {

class ShadingUnit {
 public:
  explicit ShadingUnit(PeState& pe) : pe_(pe) {}

  /// Shades `r` into its pixel at `now`; returns the cycles. Its outputs are then output(0 .. outputs() − 1).
  uint64_t take(const MachineRay& r, PixelSum& pixel, int32_t& primary_id, uint64_t now);
  size_t outputs() const { return 1 + out_.rays.size(); }
  Output output(size_t k) const {
    return k == 0 ? Output{FifoId::Ends, Output::What::End} : Output{FifoId::Spawn, Output::What::Item};
  }
  /// Output k > 0's ray, numbered now: call it once, when the scheduler first tries to write it
  /// (rays are numbered in the order they are made, and a write may wait for room).
  MachineRay spawn(const MachineRay& parent, size_t k);
  /// The kinds of ray the current one spawns, in output order (output k is spawned_kind(k − 1)).
  RayKind spawned_kind(size_t i) const { return out_.rays[i].kind; }

 private:
  PeState& pe_;
  ShadeOut out_;
};

}  // namespace rtm
