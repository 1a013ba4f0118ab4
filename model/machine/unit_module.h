// What every unit module of a PE has: a port for each FIFO the FIFO table (units/fifo_table.h)
// says its unit reads or writes, named after the FIFO (search_fifo_in, ends_fifo_out, ...), and
// one way to write a unit's output. The modules only read their FIFOs, call their unit, wait, and
// write: what the work is and where it goes is the unit's (units/).
#pragma once

#include <array>
#include <initializer_list>
#include <memory>

#include <systemc>

#include "machine/metered_fifo.h"
#include "machine/pe_context.h"
#include "units/output.h"

namespace rtm {

class UnitModule : public sc_core::sc_module {
 public:
  template <class T>
  using In = sc_core::sc_port<sc_core::sc_fifo_in_if<T>, 1, sc_core::SC_ZERO_OR_MORE_BOUND>;
  template <class T>
  using Out = sc_core::sc_port<sc_core::sc_fifo_out_if<T>, 1, sc_core::SC_ZERO_OR_MORE_BOUND>;

  /// Binds this module's port for `id` (in or out, as the table says) to a channel.
  void bind(FifoId id, MeteredFifo<MachineRay>& f);
  void bind(FifoId id, MeteredFifo<RayEnd>& f);

 protected:
  /// `kinds`: the units this module runs (an intersection unit runs a MAC and a root unit).
  UnitModule(sc_core::sc_module_name name, PeContext& ctx, std::initializer_list<UnitKind> kinds);

  In<MachineRay>& rays_in(FifoId id) { return *rays_in_[size_t(id)]; }
  bool has_input(FifoId id) const { return rays_in_[size_t(id)] && rays_in_[size_t(id)]->size() > 0; }
  In<RayEnd>& ends_in() { return *ends_in_; }

  /// Writes a unit's output for ray `r` (waiting while its FIFO is full) and records it.
  void write(const Output& o, const MachineRay& r, UnitKind kind, int index, Sleeper& sleep);

  PeContext& ctx_;

 private:
  std::array<std::unique_ptr<In<MachineRay>>, kFifoCount> rays_in_;
  std::array<std::unique_ptr<Out<MachineRay>>, kFifoCount> rays_out_;
  std::unique_ptr<In<RayEnd>> ends_in_;
  std::unique_ptr<Out<RayEnd>> ends_out_;
};

}  // namespace rtm
