// One of the PE's replicated object-search units (paper §4): examines the ray's current voxel,
// finds the next one by 3DDDA, and routes the ray by the examined voxel's occupancy.
#pragma once

#include <systemc>

#include "machine/machine_ray.h"
#include "machine/pe_context.h"

namespace rtm {

class SearchUnit : public sc_core::sc_module {
 public:
  sc_core::sc_fifo_in<MachineRay> rays_in{"rays_in"};          ///< from the front buffer (shared by all units)
  sc_core::sc_fifo_out<MachineRay> occupied_out{"occupied_out"};  ///< to the intersection stage
  sc_core::sc_fifo_out<MachineRay> feedback_out{"feedback_out"};  ///< empty voxel: back to the front buffer
  sc_core::sc_fifo_out<MachineRay> shade_out{"shade_out"};        ///< left the grid: shadow ray reached its light, or background
  sc_core::sc_fifo_out<RayEnd> ends_out{"ends_out"};              ///< left the grid with nothing to add

  SC_HAS_PROCESS(SearchUnit);
  SearchUnit(sc_core::sc_module_name name, PeContext& ctx);
  void trace(sc_core::sc_trace_file* tf, const std::string& prefix) { probe_.trace(tf, prefix, &ctx_.window); }

 private:
  void run();

  PeContext& ctx_;
  std::unique_ptr<Sleeper> sleep_;
  UnitProbe probe_;
};

}  // namespace rtm
