// The front buffer at the head of the PE's macro-pipeline (paper §4.2) as a module: it merges the
// host's primary rays with the rays fed back by the stages and hands them to the search units,
// following its policy (units/front_buffer.h).
#pragma once

#include <systemc>

#include "machine/local_memory.h"
#include "machine/unit_module.h"
#include "units/front_buffer.h"

namespace rtm {

class FrontBufferModule : public UnitModule {
 public:
  SC_HAS_PROCESS(FrontBufferModule);
  /// `finished` is notified when every ray of the PE's part of the frame has ended.
  FrontBufferModule(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem,
                    sc_core::sc_event& finished);

  const FrontBufferPolicy<MachineRay>& policy() const { return policy_; }
  void trace(Waveform& wave) override;

 private:
  struct Ops;
  struct FrontOps;
  void run();

  std::unique_ptr<Sleeper> sleep_;
  LocalMemory& mem_;
  FrontBufferPolicy<MachineRay> policy_;
  sc_core::sc_event& finished_event_;
  Pipeline<MachineRay> pipe_;
  UnitProbe probe_;
  int traced_waiting_ = 0;
};

}  // namespace rtm
