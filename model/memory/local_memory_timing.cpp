#include "memory/local_memory_timing.h"

#include <algorithm>
#include <stdexcept>

namespace rtm {

LocalMemoryTiming::Config LocalMemoryTiming::Config::from(const MachineConfig& c) {
  return {c.memory_ports,
          c.memory_banks,
          uint64_t(c.memory_interleave_bytes),
          uint64_t(c.memory_latency),
          uint64_t(c.memory_bytes_per_cycle),
          c.memory_arbitration};
}

LocalMemoryTiming::LocalMemoryTiming(const Config& c, std::vector<std::string> requesters)
    : config_(c) {
  if (c.ports < 0 || c.banks < 0 || c.interleave_bytes < 1 || c.latency < 1 ||
      c.bytes_per_cycle < 1)
    throw std::invalid_argument(
        "local memory: ports and banks must be >= 0, granule, latency and width >= 1");
  if (requesters.empty()) throw std::invalid_argument("local memory: no requester");
  for (std::string& name : requesters) requesters_.push_back({std::move(name)});
  port_stats_.resize(size_t(c.ports));
  port_booked_.resize(size_t(c.ports));
  bank_stats_.resize(size_t(c.banks));
  bank_booked_.resize(size_t(c.banks));
}

LocalMemoryTiming::Ticket LocalMemoryTiming::request(int requester, uint64_t address,
                                                     uint64_t bytes, uint64_t cycle) {
  if (requester < 0 || size_t(requester) >= requesters_.size())
    throw std::invalid_argument("local memory: no requester " + std::to_string(requester));
  if (bytes == 0) throw std::invalid_argument("local memory: a request of 0 bytes");
  if (cycle < open_from_)
    throw std::logic_error("local memory: a request for cycle " + std::to_string(cycle) +
                           ", but cycles before " + std::to_string(open_from_) + " are closed");
  // A request for a later cycle closes the cycle of those waiting: none can join them now.
  if (!waiting_.empty() && waiting_.front().cycle < cycle) admit_waiting();
  open_from_ = cycle;
  const Request r{next_ticket_++, requester, address, bytes, cycle};
  if (config_.arbitration == MemoryArbitration::Fcfs)
    admit(r);
  else
    waiting_.push_back(r);
  return r.ticket;
}

void LocalMemoryTiming::resolve(uint64_t cycle) {
  if (!waiting_.empty() && waiting_.front().cycle <= cycle) admit_waiting();
  open_from_ = std::max(open_from_, cycle + 1);
}

LocalMemoryTiming::Grant LocalMemoryTiming::collect(Ticket t) {
  Grant g;
  if (!grants_.take(t, g))
    throw std::logic_error(
        "local memory: request " + std::to_string(t) +
        (t < next_ticket_ ? " is not resolved yet, or was collected" : " was never made"));
  return g;
}

void LocalMemoryTiming::admit_waiting() {
  const int n = int(requesters_.size());
  auto rank = [&](const Request& r) {
    return config_.arbitration == MemoryArbitration::RoundRobin ? (r.requester - pointer_ + n) % n
                                                                : r.requester;
  };
  // Stable: one requester's requests keep the order they were made in. (Most cycles have one
  // request, and the sort's buffer costs an allocation.)
  if (waiting_.size() > 1)
    std::stable_sort(waiting_.begin(), waiting_.end(),
                     [&](const Request& a, const Request& b) { return rank(a) < rank(b); });
  pointer_ = (waiting_.front().requester + 1) % n;
  for (const Request& r : waiting_) admit(r);
  waiting_.clear();
}

void LocalMemoryTiming::admit(const Request& r) {
  forget_before(r.cycle);
  const uint64_t n = beats(r.bytes);
  if (config_.banks == 1) return admit_one_bank(r, n);
  bank_uses(r.address, r.bytes, uses_);
  // Conflicts: the banks its unloaded schedule would find booked.
  conflicting_.clear();
  for (const Use& u : uses_)
    if (bank_booked_[size_t(u.bank)].booked(r.cycle + u.beat)) conflicting_.push_back(u.bank);
  std::sort(conflicting_.begin(), conflicting_.end());
  conflicting_.erase(std::unique(conflicting_.begin(), conflicting_.end()), conflicting_.end());
  for (int b : conflicting_) ++bank_stats_[size_t(b)].conflicts;

  // The earliest start from the issue cycle on; each step skips only starts that cannot be it.
  uint64_t start = r.cycle;
  int port = -1;
  for (;;) {
    const uint64_t banks_from = first_free_banks(uses_, start);
    if (banks_from != start) {
      start = banks_from;
      continue;
    }
    if ((port = free_port(start, n)) >= 0) break;
    start = next_start(start);
  }

  for (const Use& u : uses_) {
    bank_booked_[size_t(u.bank)].book(start + u.beat);
    ++bank_stats_[size_t(u.bank)].busy_cycles;
  }
  grant(r, n, start, port);
}

/// admit() with one bank, in closed form: every beat uses it, so its uses are the request's
/// cycles start .. start + n - 1 and the first booked of them is the one admit() would find first.
void LocalMemoryTiming::admit_one_bank(const Request& r, uint64_t n) {
  // With one port too, every request books the bank's cycles and the port's alike: one table
  // serves both.
  const bool shared = config_.ports == 1;
  BookedCycles& bank = shared ? port_booked_[0] : bank_booked_[0];
  // The first booked cycle of the beats from `start` on, or kNone.
  auto first_booked = [&](uint64_t start) {
    const uint64_t b = bank.next_booked(start);
    return b != BookedCycles::kNone && b < start + n ? b : BookedCycles::kNone;
  };
  if (first_booked(r.cycle) != BookedCycles::kNone) ++bank_stats_[0].conflicts;
  uint64_t start = r.cycle;
  int port = -1;
  for (;;) {
    if (const uint64_t b = first_booked(start); b != BookedCycles::kNone) {
      start = bank.next_free(b) - (b - start);
      continue;
    }
    // The bank free for the beats is the one port free for them.
    if (shared) {
      port = 0;
      break;
    }
    if ((port = free_port(start, n)) >= 0) break;
    start = next_start(start);
  }
  if (!shared) bank.book(start, n);
  bank_stats_[0].busy_cycles += n;
  grant(r, n, start, port);
}

/// Books the request's port from `start` and keeps its grant and statistics.
void LocalMemoryTiming::grant(const Request& r, uint64_t n, uint64_t start, int port) {
  port_booked_[size_t(port)].book(start, n);
  port_stats_[size_t(port)].busy_cycles += n;
  RequesterStats& s = requesters_[size_t(r.requester)];
  ++s.requests;
  s.bytes += r.bytes;
  s.stall_cycles += start - r.cycle;
  grants_.put(r.ticket, {r.cycle, start, start + config_.latency + n - 1, port});
}

/// The banks each beat uses, into `uses`.
void LocalMemoryTiming::bank_uses(uint64_t address, uint64_t bytes, std::vector<Use>& uses) const {
  uses.clear();
  if (config_.banks == 0) return;
  const uint64_t w = config_.bytes_per_cycle, g = config_.interleave_bytes,
                 banks = uint64_t(config_.banks);
  for (uint64_t k = 0; k * w < bytes; ++k) {
    const uint64_t lo = address + k * w, hi = address + std::min(bytes, (k + 1) * w);
    // Consecutive granules lie in distinct banks, up to `banks` of them: a beat over more uses
    // every bank.
    const uint64_t first = lo / g, last = std::min((hi - 1) / g, first + banks - 1);
    for (uint64_t granule = first; granule <= last; ++granule)
      uses.push_back({k, int(granule % banks)});
  }
}

/// `start` if every bank is free in the beat that uses it, else the earliest start at which the
/// first use found booked is free (no start before it can be free for that use).
uint64_t LocalMemoryTiming::first_free_banks(const std::vector<Use>& uses, uint64_t start) const {
  for (const Use& u : uses) {
    const BookedCycles& b = bank_booked_[size_t(u.bank)];
    if (b.booked(start + u.beat)) return b.next_free(start + u.beat) - u.beat;
  }
  return start;
}

/// The lowest-numbered port free in cycles start .. start + beats - 1, or -1; with ports = 0 a new
/// port when none is.
int LocalMemoryTiming::free_port(uint64_t start, uint64_t beats) {
  for (size_t p = 0; p < port_booked_.size(); ++p) {
    const uint64_t next = port_booked_[p].next_booked(start);
    if (next == BookedCycles::kNone || next >= start + beats) return int(p);
  }
  if (config_.ports > 0) return -1;
  port_booked_.emplace_back();
  port_stats_.emplace_back();
  return int(port_booked_.size() - 1);
}

/// No request starts before `cycle` any more: its bookings before it are history.
void LocalMemoryTiming::forget_before(uint64_t cycle) {
  if (cycle <= forgotten_before_) return;
  forgotten_before_ = cycle;
  for (auto* booked : {&port_booked_, &bank_booked_})
    for (BookedCycles& b : *booked) b.forget_before(cycle);
}

/// After no port was free for a request's beats from `start`: the earliest start any port may
/// take. A port booked in cycle b of those beats has b in the beats of every start up to b, so it
/// can start no earlier than the first free cycle after b.
uint64_t LocalMemoryTiming::next_start(uint64_t start) const {
  uint64_t next = BookedCycles::kNone;
  for (const BookedCycles& p : port_booked_)
    next = std::min(next, p.next_free(p.next_booked(start)));
  return std::max(next, start + 1);
}

}  // namespace rtm
