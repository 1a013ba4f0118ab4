// A processing element: local memory and the three-stage macro-pipeline of paper Fig. 1.
//
//   front buffer ─► search units (K) ─┬─► intersection units (M: MAC ► root/sort) ─┬─► shading
//        ▲  ▲  ▲                      │ empty voxel                      │ no hit   │ spawned rays
//        │  │  └──────────────────────┘                                  │          │
//        │  └────────────────────────────────────────────────────────────┘          │
//        └──────────────────────────────────────────────────────────────────────────┘
#pragma once

#include <memory>
#include <vector>

#include <systemc>

#include "machine/front_buffer.h"
#include "machine/intersection_stage.h"
#include "machine/local_memory.h"
#include "machine/search_unit.h"
#include "machine/shading_stage.h"

namespace rtm {

/// What the host and the machine see of a PE, however its pipeline is simulated: the SystemC
/// modules below, or the PE engine (engine_pe.h).
class PeBase : public sc_core::sc_module {
 public:
  PeContext ctx;
  LocalMemory memory;
  sc_core::sc_event finished_event;  ///< every ray of the PE's part of the frame has ended

  virtual bool finished() const = 0;
  /// Every FIFO, for statistics and deadlock reports.
  virtual std::vector<std::pair<std::string, const FifoStats*>> fifo_stats() = 0;
  virtual std::string occupancy_report() = 0;
  virtual void trace(sc_core::sc_trace_file* tf) = 0;

 protected:
  /// `pixels`: how many pixels of the screen this PE renders.
  PeBase(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units, size_t pixels,
         Timekeeper* keeper);
};

/// A PE as SystemC modules, one per block of the paper's figure.
class Pe : public PeBase {
 public:
  // The channels between the blocks.
  MeteredFifo<MachineRay> search_fifo, intersect_fifo, shade_fifo;
  MeteredFifo<MachineRay> feedback_search, feedback_intersect;
  std::unique_ptr<MeteredFifo<MachineRay>> spawn_fifo;  ///< left out when the scene spawns no rays
  MeteredFifo<RayEnd> ends_fifo;

  FrontBuffer front;
  std::vector<std::unique_ptr<SearchUnit>> search;
  std::unique_ptr<LaneDispatcher> lanes;  ///< with more than one intersection unit
  std::vector<std::unique_ptr<IntersectionStage>> intersection;  ///< the paper has one; more is an option
  ShadingStage shading;

  Pe(sc_core::sc_module_name name, int index, const MachineConfig& c, const PeUnits& units, size_t pixels,
     sc_core::sc_clock* clock, Timekeeper* keeper);

  bool finished() const override { return front.finished(); }
  std::vector<std::pair<std::string, const FifoStats*>> fifo_stats() override;
  std::string occupancy_report() override;
  void trace(sc_core::sc_trace_file* tf) override;

 private:
  template <class T>
  std::vector<MeteredFifo<T>*> fifos_of();
};

}  // namespace rtm
