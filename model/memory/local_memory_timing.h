// The timing of a PE's local memory (docs/memory.md, "Memory timing model"): ports, banks with
// interleaving, an access latency, a port width and an arbiter. Plain C++, no SystemC, and no
// data: it only says when each request is complete. Each scheduler is to keep one per PE and make
// the same requests in the same order (both call the units in one order within a cycle, their
// rank), so both get the same grants.
//
// A request. (requester, address A, bytes B, issue cycle). It moves in T = ceil(B / W) beats, one
// a cycle (W: bytes_per_cycle), beat k carrying bytes [A + kW, min(A + (k+1)W, A + B)). Started at
// cycle s, it holds one port in cycles s .. s+T-1, and in cycle s+k every bank holding a byte of
// beat k (byte a lies in bank floor(a / G) mod banks, G the interleave granule). A port or a bank
// serves one beat a cycle. Its data is complete (a write done) at
//
//     completion = s + latency + T - 1,
//
// so a request that starts when it is issued takes unloaded_latency(B) = latency + T - 1 cycles,
// and its stall is s - issue. ports = 0: as many ports as the requests need (never a port
// conflict); banks = 0: never a bank conflict; both 0: an ideal memory, every request unloaded.
//
// Arbitration. Requests are admitted oldest issue cycle first; the policy orders the requests of
// one cycle (R requesters, numbered 0 .. R-1):
//   round_robin     by (requester - p) mod R, then in the order made. p starts at 0; after each
//                   cycle with requests it is one past the requester admitted first, so the first
//                   place rotates among the requesters that keep asking.
//   fixed_priority  by requester number, lower first, then in the order made.
//   fcfs            in the order made.
// Each request, as it is admitted, books for good the earliest start s >= its issue cycle at which
// a port is free for its T cycles (the lowest-numbered such port) and every bank its beats use is
// free in that beat's cycle. This is a reservation table, the scheduler of a controller that books
// each request as it admits it: nothing booked ever moves, so a grant depends only on the requests
// admitted before it; a later request may still take a slot before an earlier one's start where
// its own port and banks are free.
//
// When a grant is known. Under round_robin and fixed_priority a request's place depends on the
// other requests of its cycle, so the requests of a cycle are resolved together: by resolve(c) for
// their cycle or a later one, or as soon as a request for a later cycle is made (none can join them
// then). Under fcfs nothing made later goes first, so request() books each request at once and its
// grant is known on return. Since latency >= 1, a request is complete a cycle after its issue at
// the earliest: a unit that calls resolve(now - 1) before asking at cycle now whether its data has
// come always has the grant.
//
// Statistics: per requester its requests, bytes and stall cycles (the sum of s - issue); per port
// the cycles it carried a beat; per bank the cycles it served a beat and its conflicts: requests
// that, had they started when issued, would have needed it in a cycle it was already booked
// (counted once per request and bank).
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "config/config.h"
#include "memory/booked_cycles.h"

namespace rtm {

class LocalMemoryTiming {
 public:
  struct Config {
    int ports = 0;  ///< 0: as many as needed
    int banks = 0;  ///< 0: no bank conflicts
    uint64_t interleave_bytes = 4;
    uint64_t latency = 1;
    uint64_t bytes_per_cycle = 4;
    MemoryArbitration arbitration = MemoryArbitration::RoundRobin;

    /// The machine's memory_* keys.
    static Config from(const MachineConfig& c);
  };

  struct Grant {
    uint64_t issue = 0;
    uint64_t start = 0;       ///< the cycle of its first beat
    uint64_t completion = 0;  ///< its data complete, or the write done
    int port = 0;
    uint64_t stall() const { return start - issue; }
  };

  struct RequesterStats {
    std::string name;
    uint64_t requests = 0;
    uint64_t bytes = 0;
    uint64_t stall_cycles = 0;
  };
  struct PortStats {
    uint64_t busy_cycles = 0;
  };
  struct BankStats {
    uint64_t busy_cycles = 0;
    uint64_t conflicts = 0;
  };

  using Ticket = uint64_t;

  /// `requesters`: their names, in the numbering requests use. Throws std::invalid_argument for a
  /// configuration out of range or no requester.
  LocalMemoryTiming(const Config& c, std::vector<std::string> requesters);

  uint64_t beats(uint64_t bytes) const {
    return (bytes + config_.bytes_per_cycle - 1) / config_.bytes_per_cycle;
  }
  uint64_t unloaded_latency(uint64_t bytes) const { return config_.latency + beats(bytes) - 1; }

  /// Makes a request. Cycles never go back: a request for a cycle before an earlier request's, or
  /// for a cycle already resolved, throws std::logic_error; a bad requester or 0 bytes,
  /// std::invalid_argument.
  Ticket request(int requester, uint64_t address, uint64_t bytes, uint64_t cycle);
  /// No more requests will be made for cycles up to `cycle`: resolves those waiting.
  void resolve(uint64_t cycle);
  bool resolved(Ticket t) const { return grants_.has(t); }
  /// The request's grant, which is forgotten; throws std::logic_error if it is not resolved yet,
  /// or was collected.
  Grant collect(Ticket t);

  /// The earliest cycle a request may still be made for.
  uint64_t open_from() const { return open_from_; }
  const Config& config() const { return config_; }
  const std::vector<RequesterStats>& requesters() const { return requesters_; }
  /// With ports = 0: as many as were ever needed at once.
  const std::vector<PortStats>& ports() const { return port_stats_; }
  /// Empty with banks = 0.
  const std::vector<BankStats>& banks() const { return bank_stats_; }

 private:
  struct Request {
    Ticket ticket;
    int requester;
    uint64_t address, bytes, cycle;
  };
  struct Use {
    uint64_t beat;
    int bank;
  };
  /// The grants not yet collected, by ticket. Tickets come in sequence and a PE's units collect
  /// theirs within the few items they hold, so the slot of a ticket's low bits is nearly always
  /// free for it: a table lookup, no allocation; a ticket whose slot is taken goes in `others`.
  class Grants {
   public:
    bool has(Ticket t) const {
      const Slot& s = slots_[t & kMask];
      return (s.used && s.ticket == t) || (!others_.empty() && others_.count(t) != 0);
    }
    void put(Ticket t, const Grant& g) {
      Slot& s = slots_[t & kMask];
      if (s.used)
        others_[t] = g;
      else
        s = {t, g, true};
    }
    /// Removes t's grant into g; false if there is none.
    bool take(Ticket t, Grant& g) {
      Slot& s = slots_[t & kMask];
      if (s.used && s.ticket == t) {
        g = s.grant;
        s.used = false;
        return true;
      }
      const auto it = others_.find(t);
      if (it == others_.end()) return false;
      g = it->second;
      others_.erase(it);
      return true;
    }

   private:
    static constexpr Ticket kMask = 1023;
    struct Slot {
      Ticket ticket = 0;
      Grant grant;
      bool used = false;
    };
    std::vector<Slot> slots_ = std::vector<Slot>(kMask + 1);
    std::unordered_map<Ticket, Grant> others_;
  };

  void admit_waiting();
  void admit(const Request& r);
  void admit_one_bank(const Request& r, uint64_t n);
  void grant(const Request& r, uint64_t n, uint64_t start, int port);
  void bank_uses(uint64_t address, uint64_t bytes, std::vector<Use>& uses) const;
  uint64_t first_free_banks(const std::vector<Use>& uses, uint64_t start) const;
  int free_port(uint64_t start, uint64_t beats);
  /// The next start worth trying after no port is free at `start`.
  uint64_t next_start(uint64_t start) const;
  void forget_before(uint64_t cycle);

  Config config_;
  std::vector<RequesterStats> requesters_;
  std::vector<PortStats> port_stats_;
  std::vector<BankStats> bank_stats_;
  std::vector<BookedCycles> port_booked_, bank_booked_;  ///< none before the oldest open request
  std::vector<Request> waiting_;  ///< the requests of one cycle, not yet admitted
  std::vector<Use> uses_;         ///< the request being admitted's, kept to reuse its storage
  std::vector<int> conflicting_;  ///< likewise
  Grants grants_;
  Ticket next_ticket_ = 0;
  uint64_t open_from_ = 0;  ///< the earliest cycle a request may still be made for
  uint64_t forgotten_before_ = 0;
  int pointer_ = 0;  ///< round robin: the requester first in the next cycle's order
};

}  // namespace rtm
