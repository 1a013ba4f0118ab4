#include "machine/pe.h"

#include "units/front_buffer.h"

namespace rtm {
namespace {
PeContext make_context(int index, const MachineConfig& c, const PeUnits& units,
                       Timekeeper* keeper) {
  PeContext ctx;
  ctx.keeper = keeper;
  ctx.pe = index;
  ctx.units = units;
  ctx.config = c;
  ctx.period = sc_core::sc_time(c.clock_ns, sc_core::SC_NS);
  ctx.cycle = ctx.period.value();
  ctx.counters.size_for(c);
  return ctx;
}

}  // namespace

Pe::Pe(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units,
       size_t pixels, Timekeeper* keeper)
    : sc_module(name), ctx(make_context(index, c, units, keeper)), memory("memory", ctx, pixels) {
  memory.rays_expected =
      c.partition == Partition::Dynamic ? kRaysUnknown : pixels * size_t(c.frames);
}

}  // namespace rtm
