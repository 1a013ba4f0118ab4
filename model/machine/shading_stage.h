// The shading stage (paper §6): adds brightness into the PE's frame buffer and spawns shadow,
// reflected and transmitted rays back into the front buffer.
#pragma once

#include <systemc>

#include "machine/local_memory.h"
#include "machine/machine_ray.h"
#include "render/shade.h"

namespace rtm {

class ShadingStage : public sc_core::sc_module {
 public:
  sc_core::sc_fifo_in<MachineRay> rays_in{"rays_in"};       ///< hits, shadow rays that reached their light, misses
  sc_core::sc_fifo_out<MachineRay> spawn_out{"spawn_out"};  ///< new rays, to the front buffer
  sc_core::sc_fifo_out<RayEnd> ends_out{"ends_out"};        ///< every ray ends here

  SC_HAS_PROCESS(ShadingStage);
  ShadingStage(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem);
  void trace(sc_core::sc_trace_file* tf, const std::string& prefix) { probe_.trace(tf, prefix, &ctx_.window); }

 private:
  void run();

  PeContext& ctx_;
  LocalMemory& mem_;
  UnitProbe probe_;
};

}  // namespace rtm
