// One PE's local memory as its units use it (docs/memory.md, "How the units use it"): the timing
// (memory/local_memory_timing.h), the record addresses (memory/records.h), the MACs' coefficient
// RAMs and the optional voxel cache, with the requesters numbered in one order both schedulers
// share: the search units, the intersection lanes, the front buffer, shading, the host.
//
// The timing rule. A unit requests what an item reads or writes when it takes the item, at that
// PE cycle, and says when its plan needs the data: the item's latency already counts the request's
// unloaded time (or hides it within a constant of the unit). The requests travel with the item
// (MemoryWait); when its result is due, step_unit (units/unit_step.h) asks when the data really
// came, and a result whose data came late waits for it exactly as for a full output FIFO.
//
// The host's traffic. The PE's network interface writes what a transfer brings into local memory
// in bursts of kHostBurstBytes as it comes in, spread evenly over the transfer's last hop (so a
// scene copy or a block of rays streaming in while the units work contends with their requests);
// the bursts are requested from the timing, before any unit's request of their cycle or a later
// one. The gather's read comes after the PE has finished, when nothing else uses the memory: it
// is counted, not timed.
//
// The fast path. With an ideal memory (memory_ports = 0 and memory_banks = 0) every request takes
// its unloaded time, so no plan is ever late: requests are only counted, and no reservation table
// is kept.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "memory/coefficient_ram.h"
#include "memory/local_memory_timing.h"
#include "memory/records.h"
#include "memory/voxel_cache.h"

namespace rtm {

/// The requests an item waits for, and the plan they were made for.
struct MemoryWait {
  struct Pending {
    LocalMemoryTiming::Ticket ticket;
    uint64_t need;  ///< cycles after the item was taken that its plan needs the data at
  };
  /// The requests: nearly every item makes one or two, kept inline (an item's requests are made
  /// and collected millions of times a frame, a heap block each in a vector), the rest beyond.
  class PendingList {
   public:
    bool empty() const { return size_ == 0; }
    size_t size() const { return size_; }
    Pending& operator[](size_t i) { return i < kInline ? inline_[i] : more_[i - kInline]; }
    void push_back(const Pending& p) {
      if (size_ < kInline)
        inline_[size_] = p;
      else
        more_.push_back(p);
      ++size_;
    }
    /// Keeps the first n (n <= size()).
    void resize(size_t n) {
      more_.resize(n > kInline ? n - kInline : 0);
      size_ = n;
    }

   private:
    static constexpr size_t kInline = 2;
    Pending inline_[kInline]{};
    size_t size_ = 0;
    std::vector<Pending> more_;
  };
  PendingList pending;
  uint64_t latency = 0;  ///< the item's latency in the plan (Work::cycles)
  int64_t ready =
      INT64_MIN;  ///< cycles after acceptance the result can leave at, by the grants collected
  int who = 0;    ///< the requester (one per item)
  bool counted = false;  ///< its wait is in the requester's wait cycles

  bool empty() const { return pending.empty() && ready == INT64_MIN; }
};

/// What one PE's local memory did in a frame, for the statistics.
struct MemoryUse {
  struct Requester {
    std::string name;
    uint64_t requests = 0, bytes = 0;
    uint64_t stall_cycles =
        0;  ///< what contention added to its requests' latencies (the grants' stalls)
    uint64_t wait_cycles =
        0;  ///< what its results waited past their due time for data (the pipeline stalled)
    uint64_t access_cycles =
        0;  ///< its reads' times, issue to data (posted writes: none), however they overlap
  };
  bool ideal = true;  ///< memory_ports = 0 and memory_banks = 0: every request unloaded
  std::vector<Requester> requesters;
  std::vector<uint64_t> port_busy_cycles;  ///< empty with the ideal memory (no ports kept)
  uint64_t beats = 0;                      ///< what the ports carried in all
  uint64_t bank_conflicts = 0;
  uint64_t coef_hits = 0, coef_misses = 0,
           coef_evictions = 0;  ///< the lanes' coefficient RAMs, summed
  bool voxel_cache = false;
  uint64_t cache_hits = 0, cache_misses = 0, cache_line_fills = 0;

  uint64_t wait_cycles() const;
  uint64_t access_cycles() const;
};

class PeMemory {
 public:
  using Stats = LocalMemoryTiming::RequesterStats;

  PeMemory(const MachineConfig& c, const SceneImage& image, uint64_t pixels);

  // Requester numbers.
  int search(int k) const { return k; }
  int lane(int k) const { return search_units_ + k; }
  int front() const { return search_units_ + lanes_; }
  int shading() const { return front() + 1; }
  int host() const { return front() + 2; }

  bool ideal() const { return !timing_; }
  uint64_t unloaded(uint64_t bytes) const { return latency_ + beats_of(bytes) - 1; }

  /// A request made at PE cycle `cycle` for an item whose plan needs its data `need` cycles after
  /// it was taken (need >= unloaded(bytes): on time when unloaded). The unit sets w.latency.
  void request(int who, uint64_t address, uint64_t bytes, uint64_t cycle, uint64_t need,
               MemoryWait& w) {
    if (timing_) return request_timed(who, address, bytes, cycle, need, w);
    // The fast path, inline: every unit asks this on nearly every item. Unloaded, the data is
    // there need - unloaded(bytes) >= 0 cycles before the plan needs it.
    beats_ += beats_of(bytes);
    count(who, bytes);
    if (need > 0) access_cycles_[size_t(who)] += visible(unloaded(bytes), need, w.latency);
  }
  /// A read of voxel data (a search unit's entry, a lane's list) through the voxel cache if there
  /// is one: the cycles the plan gives it (its unloaded time; a cache hit 1, a miss its lines'
  /// fill) and what to request of the memory (bytes 0: a hit, nothing).
  struct VoxelRead {
    uint64_t cycles, address, bytes;
  };
  VoxelRead voxel_read(uint64_t address, uint64_t bytes);
  /// A write nobody waits for (a posted write).
  void post(int who, uint64_t address, uint64_t bytes, uint64_t cycle);
  /// Traffic that is counted but not timed (the host's gather: docs/memory.md).
  void count(int who, uint64_t bytes) {
    Stats& s = counted_[size_t(who)];
    ++s.requests;
    s.bytes += bytes;
  }
  /// A host transfer of `bytes` to `address` arriving over PE cycles [from, to]: its bursts, the
  /// last at `to`, are posted as the cycles come (see the top).
  void host_write(uint64_t address, uint64_t bytes, uint64_t from, uint64_t to);
  /// The frame is over: the host's bursts still to come are posted (they meet no other request).
  void end_of_frame();

  /// When an item accepted at `accepted` (ticks) and due at `due` may leave, checked at `now`
  /// (ticks, >= due; `cycle`: ticks a PE cycle): max(due, each request's completion plus what the
  /// plan had after it, latency - need); a request whose grant is not known yet keeps it at
  /// least a cycle past now.
  uint64_t ready(MemoryWait& w, uint64_t accepted, uint64_t due, uint64_t now, uint64_t cycle);

  const MemoryAddresses& addresses() const { return addresses_; }
  /// Primitive p's coefficient record, in bytes (sparse schedules: its non-zero words and a mask).
  uint64_t coef_bytes(uint32_t p) const { return coef_bytes_[p]; }
  CoefficientRam& coef_ram(int lane) { return coef_rams_[size_t(lane)]; }
  const std::vector<CoefficientRam>& coef_rams() const { return coef_rams_; }
  /// voxel_cache_bytes = 0: none.
  VoxelCache* voxel_cache() { return cache_ ? &*cache_ : nullptr; }
  const VoxelCache* voxel_cache() const { return cache_ ? &*cache_ : nullptr; }

  /// Per requester (named), its requests, bytes and stall cycles; the host's gather counted, not
  /// timed.
  std::vector<Stats> requesters() const;
  /// The timing's ports and banks; null with the ideal memory (none kept).
  const LocalMemoryTiming* timing() const { return timing_.get(); }
  /// Beats moved in all (what the ports carried, however many there were).
  uint64_t beats() const { return beats_; }
  MemoryUse use() const;

 private:
  /// The beats a port moves `bytes` in.
  uint64_t beats_of(uint64_t bytes) const { return (bytes + width_ - 1) / width_; }
  void request_timed(int who, uint64_t address, uint64_t bytes, uint64_t cycle, uint64_t need,
                     MemoryWait& w);
  /// Of an access of `cycles`, what its item's plan does not hide: a read within a unit's constant
  /// (needed after the item's latency) hides that much of its time.
  static uint64_t visible(uint64_t cycles, uint64_t need, uint64_t latency) {
    const uint64_t hidden = need > latency ? need - latency : 0;
    return cycles > hidden ? cycles - hidden : 0;
  }
  void collect_posted();
  /// Posts the host's bursts due up to `cycle`.
  void post_host_bursts(uint64_t cycle);

  const int search_units_, lanes_;
  const uint64_t latency_, width_;
  std::unique_ptr<LocalMemoryTiming> timing_;      ///< null: the ideal memory's fast path
  std::vector<Stats> counted_;                     ///< the fast path's statistics, and the host's
  std::vector<LocalMemoryTiming::Ticket> posted_;  ///< posted writes whose grants are to be dropped
  struct Burst {
    uint64_t cycle, address, bytes;
  };
  std::deque<Burst> host_bursts_;  ///< by cycle: the host's writes still to come
  MemoryAddresses addresses_;
  std::vector<uint64_t> coef_bytes_;
  std::vector<CoefficientRam> coef_rams_;
  std::optional<VoxelCache> cache_;
  uint64_t beats_ = 0;
  std::vector<uint64_t> wait_cycles_, access_cycles_;  ///< per requester
};

}  // namespace rtm
