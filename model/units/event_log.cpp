#include "units/event_log.h"

#include <algorithm>
#include <tuple>

namespace rtm {

bool UnitEvent::operator<(const UnitEvent& o) const {
  return std::tie(time, unit, index, ray, what, fifo) <
         std::tie(o.time, o.unit, o.index, o.ray, o.what, o.fifo);
}

void write_event_log(std::ostream& out, std::vector<EventLog>& pes, uint64_t cycle) {
  static const char* const kFrom[] = {"queued", "spilled", "primary"};
  // Each PE's events are in time order already; sorting settles the order within an instant.
  std::vector<size_t> next(pes.size(), 0);
  for (EventLog& log : pes) std::stable_sort(log.events().begin(), log.events().end());
  for (;;) {
    int pe = -1;  // the PE whose next event comes first: lowest time, then lowest PE
    for (size_t p = 0; p < pes.size(); ++p)
      if (next[p] < pes[p].events().size() &&
          (pe < 0 ||
           pes[p].events()[next[p]].time < pes[size_t(pe)].events()[next[size_t(pe)]].time))
        pe = int(p);
    if (pe < 0) return;
    const UnitEvent& e = pes[size_t(pe)].events()[next[size_t(pe)]++];
    out << e.time / cycle;
    if (const uint64_t frac = e.time % cycle)
      out << "+" << frac << "t";  // off the PE clock (host arrivals)
    out << " pe" << pe << " " << unit_name(e.unit);
    if (unit_spec(e.unit).logged_by_number) out << e.index;
    out << " ray" << e.ray;
    if (e.what == UnitEvent::What::Take) {
      out << " take " << e.cycles;
      if (e.unit == UnitKind::FrontBuffer) out << " " << kFrom[e.from];
    } else {
      out << " put " << fifo_spec(e.fifo).name;
    }
    out << "\n";
  }
}

}  // namespace rtm
