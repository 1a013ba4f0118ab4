// The shading unit (paper §6) as a module: shades each ray into the PE's frame buffer and writes
// its outputs (units/shading_unit.h), several rays in flight when pipelined. Each ray generator
// (shadow, reflected, transmitted) is a child module elaborated only when the scene can spawn that
// kind of ray; its busy flag shows in waveforms.
#pragma once

#include <memory>

#include <systemc>

#include "machine/local_memory.h"
#include "machine/unit_module.h"
#include "units/shading_unit.h"

namespace rtm {

class SpawnUnit : public sc_core::sc_module {
 public:
  explicit SpawnUnit(sc_core::sc_module_name name) : sc_module(name) {}
  UnitProbe probe;
};

class ShadingModule : public UnitModule {
 public:
  SC_HAS_PROCESS(ShadingModule);
  ShadingModule(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem);
  void trace(Waveform& wave) override;

 private:
  struct Ops;
  struct WriteOps;
  void run();

  ShadingUnit unit_;
  std::unique_ptr<Sleeper> sleep_;
  LocalMemory& mem_;
  Pipeline<MachineRay> pipe_;
  ShadingWriter<MachineRay> writer_;
  UnitProbe probe_;
  std::unique_ptr<SpawnUnit> generators_[kRayKinds];  ///< by RayKind; none for primary rays
};

}  // namespace rtm
