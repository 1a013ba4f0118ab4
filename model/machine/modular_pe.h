// A PE as SystemC modules, one per block of the paper's figure, joined by the FIFOs of the FIFO
// table (units/fifo_table.h).
#pragma once

#include <memory>
#include <vector>

#include "machine/front_buffer_module.h"
#include "machine/intersection_module.h"
#include "machine/pe.h"
#include "machine/ray_stage_module.h"
#include "machine/shading_module.h"

namespace rtm {

class ModularPe : public Pe {
 public:
  ModularPe(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units,
            size_t pixels, sc_core::sc_clock* clock, Timekeeper* keeper);

  bool finished() const override { return front_->policy().finished(); }
  FifoStatsList fifo_stats() override;
  std::string occupancy_report() override;
  void trace(Waveform& wave) override;

 private:
  /// Creates the module that runs unit k of this kind.
  void create(UnitKind kind, int k, sc_core::sc_clock* clock);
  /// Creates the module that runs unit k of ray stage K (units/ray_stage.h).
  template <UnitKind K>
  UnitModule* create_stage(int k);
  /// Where FIFO f's meter is (lane: of a per-lane FIFO).
  FifoMeter& meter(const FifoSpec& f, int lane);

  // The channels, by FIFO (the table's per-lane root_fifo FIFOs live in the intersection units).
  std::array<std::unique_ptr<MeteredFifo<MachineRay>>, kFifoCount> rays_;
  std::unique_ptr<MeteredFifo<RayEnd>> ends_;

  std::unique_ptr<FrontBufferModule> front_;
  std::vector<std::unique_ptr<UnitModule>> stages_;  ///< the ray stages' units, in rank order
  std::array<std::unique_ptr<Dispatcher>, kUnitKinds> stage_dispatch_;  ///< a ray stage's
  std::unique_ptr<Dispatcher> intersect_dispatch_;
  std::vector<std::unique_ptr<IntersectionModule>>
      intersection_;  ///< the paper has one; more is an option
  std::unique_ptr<ShadingModule> shading_;
  std::array<std::vector<UnitModule*>, kUnitKinds>
      modules_;  ///< by kind, the modules that run its units
};

}  // namespace rtm
