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

  /// Shades `r` into its pixel at `now`. Its outputs are listed by outputs() and output() once it
  /// is the oldest ray in the unit (the returned Work's `out` is output(0)).
  Work take(const MachineRay& r, PixelSum& pixel, int32_t& primary_id, uint64_t now);

  // The oldest ray's outputs: results leave a pipelined unit in order.
  size_t outputs() const { return 1 + head().rays.size(); }
  Output output(size_t k) const {
    return k == 0 ? Output{FifoId::Ends, Output::What::End}
                  : Output{FifoId::Spawn, Output::What::Item};
  }
  /// Output k > 0's ray, numbered now: call it once, when the scheduler first tries to write it
  /// (rays are numbered in the order they are made, and a write may wait for room).
  MachineRay spawn(const MachineRay& parent, size_t k);
  /// The kinds of ray the oldest one spawns, in output order (output k is spawned_kind(k − 1)).
  RayKind spawned_kind(size_t i) const { return head().rays[i].kind; }
  /// The oldest ray's outputs are written.
  void retired() {
    ++head_;
    if (head_ == taken_) head_ = taken_ = 0;  // empty: start the ring over
  }

 private:
  const ShadeOut& head() const { return outs_[head_ % outs_.size()]; }

  PeState& pe_;
  std::vector<ShadeOut> outs_;  ///< a ring: the rays in the unit, from head_ to taken_
  size_t head_ = 0, taken_ = 0;
};

/// Writes the oldest shaded ray's outputs in their one order, the same under both schedulers:
/// the end first, then each spawned ray, made (numbered) once, when first tried, before it waits
/// for room. A write that finds its FIFO full is tried again from where it stopped. `Child`: how
/// the scheduler holds a spawned ray. The scheduler's operations:
///   bool write_end(const Output&)                the ray's end; false when its FIFO is full
///   Child make(size_t k)                         output k's ray (k > 0), made now
///   bool write(const Output&, const Child&)      a spawned ray; false when its FIFO is full
template <class Child>
class ShadingWriter {
 public:
  /// True when every output of the oldest ray is written.
  template <class Ops>
  bool write(const ShadingUnit& unit, Ops& ops) {
    for (; next_ < unit.outputs(); ++next_) {
      const Output o = unit.output(next_);
      if (next_ == 0) {
        if (!ops.write_end(o)) return false;
        continue;
      }
      if (!made_) {
        child_ = ops.make(next_);
        made_ = true;
      }
      if (!ops.write(o, child_)) return false;
      made_ = false;
    }
    return true;
  }
  /// The oldest ray has left: the next one's outputs start from its end.
  void retired() { next_ = 0; }

 private:
  size_t next_ = 0;  ///< the oldest ray's next output to write
  Child child_{};    ///< that output's ray, once made
  bool made_ = false;
};

}  // namespace rtm
