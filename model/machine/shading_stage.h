// The shading stage (paper §6): adds brightness into the PE's frame buffer and spawns shadow,
// reflected and transmitted rays back into the front buffer.
#pragma once

#include <memory>

#include <systemc>

#include "machine/local_memory.h"
#include "machine/machine_ray.h"
#include "render/shade.h"

namespace rtm {

/// One of shading's ray generators (shadow, reflected, transmitted): elaborated only when the
/// scene can spawn that kind of ray; its busy flag shows in waveforms.
class SpawnUnit : public sc_core::sc_module {
 public:
  explicit SpawnUnit(sc_core::sc_module_name name) : sc_module(name) {}
  UnitProbe probe;
};

class ShadingStage : public sc_core::sc_module {
 public:
  sc_core::sc_fifo_in<MachineRay> rays_in{"rays_in"};       ///< hits, shadow rays that reached their light, misses
  /// New rays, to the front buffer; left unbound when the scene spawns none.
  sc_core::sc_port<sc_core::sc_fifo_out_if<MachineRay>, 1, sc_core::SC_ZERO_OR_MORE_BOUND> spawn_out{"spawn_out"};
  sc_core::sc_fifo_out<RayEnd> ends_out{"ends_out"};        ///< every ray ends here

  SC_HAS_PROCESS(ShadingStage);
  ShadingStage(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem);
  void trace(sc_core::sc_trace_file* tf, const std::string& prefix);

 private:
  void run();

  PeContext& ctx_;
  std::unique_ptr<Sleeper> sleep_;
  LocalMemory& mem_;
  UnitProbe probe_;
  std::unique_ptr<SpawnUnit> units_[kRayKinds];  ///< by RayKind; none for primary rays
};

}  // namespace rtm
