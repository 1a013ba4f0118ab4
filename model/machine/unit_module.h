// What every unit module of a PE has: a port for each FIFO the FIFO table (units/fifo_table.h)
// says its unit reads or writes, named after the FIFO (search_fifo_in, ends_fifo_out, ...), and
// one way to write a unit's output. The modules only read their FIFOs, call their unit, wait, and
// write: what the work is and where it goes is the unit's (units/).
#pragma once

#include <array>
#include <initializer_list>
#include <memory>
#include <vector>

#include <systemc>

#include "machine/metered_fifo.h"
#include "machine/pe_context.h"
#include "units/intersection.h"
#include "units/output.h"
#include "units/unit_step.h"

namespace rtm {

/// Replicated units waiting on one FIFO (the search units, the intersection units): each ray that
/// arrives wakes the lowest-numbered waiting one (units/lane_dispatcher.h), instead
/// of leaving it to the kernel's wake-up order.
class Dispatcher : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Dispatcher);
  Dispatcher(sc_core::sc_module_name name, MeteredFifo<MachineRay>& in, int units);
  /// Unit `k` found the FIFO empty: wake it for the next ray that is its to take.
  void wait(int k) { waiting_.idle(k); }
  /// Unit `k` woke for another reason.
  void woke(int k) { waiting_.busy(k); }
  const sc_core::sc_event& event(int k) const { return *wake_[size_t(k)]; }

 private:
  void dispatch();

  MeteredFifo<MachineRay>& in_;
  LaneDispatcher waiting_;
  std::vector<std::unique_ptr<sc_core::sc_event>> wake_;
};

class UnitModule : public sc_core::sc_module {
 public:
  template <class T>
  using In = sc_core::sc_port<sc_core::sc_fifo_in_if<T>, 1, sc_core::SC_ZERO_OR_MORE_BOUND>;
  template <class T>
  using Out = sc_core::sc_port<sc_core::sc_fifo_out_if<T>, 1, sc_core::SC_ZERO_OR_MORE_BOUND>;

  /// Binds this module's port for `id` (in or out, as the table says) to a channel.
  void bind(FifoId id, MeteredFifo<MachineRay>& f);
  void bind(FifoId id, MeteredFifo<RayEnd>& f);
  /// Traces its signals into `wave`.
  virtual void trace(Waveform& wave) = 0;

 protected:
  /// `kinds`: the units this module runs (an intersection unit runs a MAC and a root unit).
  UnitModule(sc_core::sc_module_name name, PeContext& ctx, std::initializer_list<UnitKind> kinds);

  In<MachineRay>& rays_in(FifoId id) { return *rays_in_[size_t(id)]; }
  bool has_input(FifoId id) const {
    return rays_in_[size_t(id)] && rays_in_[size_t(id)]->size() > 0;
  }
  In<RayEnd>& ends_in() { return *ends_in_; }

  /// Writes a unit's output for ray `r` and records it; false (nothing written) when its FIFO is
  /// full.
  bool try_write(const Output& o, const MachineRay& r, UnitKind kind, int index);

  /// Runs a unit forever: each wake-up is units/unit_step.h's step_unit with `ops`; a unit that
  /// waits for input sleeps until `either` (its input's events | the sleeper's: a list, built
  /// once; the expression `a | b` itself would be freed after its first wait).
  template <class Item, class Ops>
  [[noreturn]] void run_unit(Pipeline<Item>& pipe, Ops& ops, Sleeper& sleep,
                             const sc_core::sc_event_or_list& either) {
    for (;;) {
      const bool waiting =
          step_unit(pipe, PeContext::now(), ctx_.period.value(), ctx_.memory.get(), ops);
      sleep.wait(waiting ? &either : nullptr);
    }
  }

  PeContext& ctx_;

 private:
  std::array<std::unique_ptr<In<MachineRay>>, kFifoCount> rays_in_;
  std::array<std::unique_ptr<Out<MachineRay>>, kFifoCount> rays_out_;
  std::unique_ptr<In<RayEnd>> ends_in_;
  std::unique_ptr<Out<RayEnd>> ends_out_;
};

}  // namespace rtm
