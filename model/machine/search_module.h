// One of the PE's replicated object-search units (paper §4) as a module: takes rays from the
// FIFO all search units share (the dispatcher wakes the lowest-numbered waiting unit) and runs
// its unit (units/search_unit.h) on each, several in flight when pipelined.
#pragma once

#include <systemc>

#include "machine/unit_module.h"
#include "units/search_unit.h"

namespace rtm {

class SearchModule : public UnitModule {
 public:
  SC_HAS_PROCESS(SearchModule);
  SearchModule(sc_core::sc_module_name name, PeContext& ctx, int index, Dispatcher& dispatcher);
  void trace(Waveform& wave) { probe_.trace(wave, name(), &ctx_.window); }

 private:
  struct Held {
    MachineRay r;
    Output out;
  };
  struct Ops;
  void run();

  SearchUnit unit_;
  std::unique_ptr<Sleeper> sleep_;
  Dispatcher& dispatcher_;
  Pipeline<Held> pipe_;
  UnitProbe probe_;
};

}  // namespace rtm
