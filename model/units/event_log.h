// The event log (`rtm render --event-log FILE`): one line per unit event, written by the units'
// own code, so either scheduler (the modules or the PE engine) writes the same log for the same
// frame, and the first line where two logs part says which unit did what differently, when.
// Format (docs/architecture.md, "The event log"):
//
//   CYCLE PE UNIT RAY EVENT [DETAIL]     e.g.   215703 pe0 search2 ray17 put intersect_fifo
//
// EVENT is `take` (the unit accepted the ray; DETAIL its work's cycles, and for the front buffer
// where the ray came from) or `put` (its result was written; DETAIL the FIFO). UNIT is the unit's
// name, with its lane for intersection units (mac0, root1); search units are named `search`
// alone: they are interchangeable, and which of them takes a ray is the scheduler's choice (in the
// modules, SystemC's) and changes nothing else. Lines are in the order of (cycle, PE, unit rank,
// lane, ray, event): the schedulers may act in a different order within one instant without
// meaning anything, so the log does not record that order.
#pragma once

#include <cstdint>
#include <ostream>
#include <vector>

#include "units/fifo_table.h"
#include "units/unit_table.h"

namespace rtm {

struct UnitEvent {
  uint64_t time;  ///< ticks
  UnitKind unit;
  uint16_t index;  ///< the unit's number among its kind
  uint32_t ray;
  enum class What : uint8_t { Take, Put } what;
  uint8_t from = 0;     ///< take at the front buffer: 0 queued, 1 spilled, 2 primary
  FifoId fifo{};        ///< put
  uint64_t cycles = 0;  ///< take: the work's cycles

  bool operator<(const UnitEvent& o) const;
};

/// One PE's events, in the order they happened.
class EventLog {
 public:
  void take(uint64_t time, UnitKind u, int index, uint32_t ray, uint64_t cycles, uint8_t from = 0) {
    events_.push_back(
        {time, u, logged(u, index), ray, UnitEvent::What::Take, from, FifoId::Search, cycles});
  }
  void put(uint64_t time, UnitKind u, int index, uint32_t ray, FifoId fifo) {
    events_.push_back({time, u, logged(u, index), ray, UnitEvent::What::Put, 0, fifo, 0});
  }
  /// The number the log gives a unit (UnitSpec::logged_by_number).
  static uint16_t logged(UnitKind u, int index) {
    return unit_spec(u).logged_by_number ? uint16_t(index) : 0;
  }
  std::vector<UnitEvent>& events() { return events_; }

 private:
  std::vector<UnitEvent> events_;
};

/// Writes every PE's events as the log's lines, in the log's order; `cycle`: the PE clock period
/// in ticks.
void write_event_log(std::ostream& out, std::vector<EventLog>& pes, uint64_t cycle);

}  // namespace rtm
