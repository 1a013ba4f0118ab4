// One of the PE's replicated object-search units (paper §4): examines the ray's current voxel,
// finds the next one by 3DDDA, and routes the ray by the examined voxel's occupancy.
#pragma once

#include "units/output.h"
#include "units/routing.h"

namespace rtm {

class SearchUnit {
 public:
  SearchUnit(PeState& pe, int index) : pe_(pe), index_(index) {}

  /// A pass (or passes, with search_walk = until_occupied) over `r`, taken at `now` (ticks): each
  /// examined voxel's entry is read from local memory (units/pe_memory.h).
  Work take(MachineRay& r, uint64_t now);
  int index() const { return index_; }

 private:
  PeState& pe_;
  int index_;
};

}  // namespace rtm
