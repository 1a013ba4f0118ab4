#include "units/pe_memory.h"

#include <algorithm>

#include "memory/scene_image.h"

namespace rtm {
namespace {

std::vector<std::string> requester_names(const MachineConfig& c) {
  std::vector<std::string> names;
  for (int k = 0; k < c.search_units; ++k) names.push_back("search" + std::to_string(k));
  for (int k = 0; k < c.intersection_units; ++k) names.push_back("lane" + std::to_string(k));
  for (const char* n : {"front_buffer", "shading", "host"}) names.push_back(n);
  return names;
}

}  // namespace

PeMemory::PeMemory(const MachineConfig& c, const SceneImage& image, uint64_t pixels)
    : search_units_(c.search_units),
      lanes_(c.intersection_units),
      latency_(uint64_t(c.memory_latency)),
      width_(uint64_t(c.memory_bytes_per_cycle)),
      addresses_(image, pixels, c),
      coef_rams_(size_t(c.intersection_units), CoefficientRam(uint32_t(c.mac_ram_primitives))) {
  const std::vector<std::string> names = requester_names(c);
  for (const std::string& n : names) counted_.push_back({n});
  wait_cycles_.assign(names.size(), 0);
  access_cycles_.assign(names.size(), 0);
  if (c.memory_ports != 0 || c.memory_banks != 0) {
    LocalMemoryTiming::Config t = LocalMemoryTiming::Config::from(c);
    // Which of two units acting in one cycle asks first is no fact of the machine (the two
    // schedulers may call them in either order), so under fcfs the requests of one cycle go in
    // requester order: first come, first served from one cycle to the next.
    if (t.arbitration == MemoryArbitration::Fcfs) t.arbitration = MemoryArbitration::FixedPriority;
    timing_ = std::make_unique<LocalMemoryTiming>(t, names);
  }
  if (c.voxel_cache_bytes > 0) cache_ = VoxelCache::from(c);
  const bool sparse = c.mac_schedule == MachineConfig::MacSchedule::Sparse;
  image.visit([&](const auto& mem) {
    for (const auto& ram : mem.rams)
      coef_bytes_.push_back(
          coef_record_bytes(c.intersection_precision_in_force(), coef_record_words(ram, sparse)));
  });
}

void PeMemory::request_timed(int who, uint64_t address, uint64_t bytes, uint64_t cycle,
                             uint64_t need, MemoryWait& w) {
  beats_ += beats_of(bytes);
  if (who != host()) post_host_bursts(cycle);
  w.who = who;
  w.pending.push_back({timing_->request(who, address, bytes, cycle), need});
}

PeMemory::VoxelRead PeMemory::voxel_read(uint64_t address, uint64_t bytes) {
  if (!cache_) return {unloaded(bytes), address, bytes};
  const uint64_t lines = cache_->access(address, bytes);
  if (lines == 0) return {1, address, 0};
  // The lines it lacks, as one burst from the first line of the access.
  const uint64_t line = cache_->line_bytes(), fill = lines * line;
  return {unloaded(fill), address / line * line, fill};
}

void PeMemory::post(int who, uint64_t address, uint64_t bytes, uint64_t cycle) {
  beats_ += beats_of(bytes);
  if (!timing_) return count(who, bytes);
  if (who != host()) post_host_bursts(cycle);
  posted_.push_back(timing_->request(who, address, bytes, cycle));
}

void PeMemory::host_write(uint64_t address, uint64_t bytes, uint64_t from, uint64_t to) {
  const uint64_t bursts = (bytes + kHostBurstBytes - 1) / kHostBurstBytes, span = to - from;
  for (uint64_t k = 0; k < bursts; ++k) {
    const uint64_t offset = k * kHostBurstBytes;
    const Burst b{from + uint64_t((unsigned __int128)span * (k + 1) / bursts), address + offset,
                  std::min(kHostBurstBytes, bytes - offset)};
    if (!timing_) {  // the ideal memory: counted at once, nothing waits for it
      post(host(), b.address, b.bytes, b.cycle);
      continue;
    }
    // A PE's transfers come one after another over its last link, so this is nearly always the end.
    host_bursts_.insert(
        std::upper_bound(host_bursts_.begin(), host_bursts_.end(), b,
                         [](const Burst& x, const Burst& y) { return x.cycle < y.cycle; }),
        b);
  }
}

void PeMemory::post_host_bursts(uint64_t cycle) {
  while (!host_bursts_.empty() && host_bursts_.front().cycle <= cycle) {
    const Burst b = host_bursts_.front();
    host_bursts_.pop_front();
    // Delivered when its transfer arrives, so never for a cycle the units have closed; the
    // maximum keeps the timing's order should a transfer's first burst fall in the cycle at hand.
    post(host(), b.address, b.bytes, std::max(b.cycle, timing_->open_from()));
  }
}

void PeMemory::end_of_frame() {
  if (timing_) post_host_bursts(UINT64_MAX);
}

void PeMemory::collect_posted() {
  posted_.erase(std::remove_if(posted_.begin(), posted_.end(),
                               [&](LocalMemoryTiming::Ticket t) {
                                 return timing_->resolved(t) && (timing_->collect(t), true);
                               }),
                posted_.end());
}

uint64_t PeMemory::ready(MemoryWait& w, uint64_t accepted, uint64_t due, uint64_t now,
                         uint64_t cycle) {
  const uint64_t now_cycle = now / cycle;
  bool unknown = false;
  if (!w.pending.empty()) {
    if (now_cycle > 0) {
      post_host_bursts(now_cycle - 1);
      timing_->resolve(now_cycle - 1);
    }
    if (!posted_.empty()) collect_posted();
    size_t kept = 0;
    for (size_t i = 0; i < w.pending.size(); ++i) {
      const MemoryWait::Pending p = w.pending[i];
      if (!timing_->resolved(p.ticket)) {
        w.pending[kept++] = p;
        unknown = true;
        continue;
      }
      const LocalMemoryTiming::Grant g = timing_->collect(p.ticket);
      w.ready =
          std::max(w.ready, int64_t(g.completion - g.issue) + int64_t(w.latency) - int64_t(p.need));
      access_cycles_[size_t(w.who)] += visible(g.completion - g.issue, p.need, w.latency);
    }
    w.pending.resize(kept);
  }
  uint64_t at = due;
  if (w.ready != INT64_MIN && w.ready > 0) at = std::max(at, accepted + uint64_t(w.ready) * cycle);
  if (unknown) return std::max(at, (now_cycle + 1) * cycle);
  if (!w.counted) {
    w.counted = true;
    wait_cycles_[size_t(w.who)] += (at - due) / cycle;
  }
  return at;
}

std::vector<PeMemory::Stats> PeMemory::requesters() const {
  if (!timing_) return counted_;
  std::vector<Stats> s = timing_->requesters();
  // The gather's read is counted beside the host's timed writes.
  s[size_t(host())].requests += counted_[size_t(host())].requests;
  s[size_t(host())].bytes += counted_[size_t(host())].bytes;
  return s;
}

}  // namespace rtm

namespace rtm {

uint64_t MemoryUse::wait_cycles() const {
  uint64_t n = 0;
  for (const Requester& r : requesters) n += r.wait_cycles;
  return n;
}

uint64_t MemoryUse::access_cycles() const {
  uint64_t n = 0;
  for (const Requester& r : requesters) n += r.access_cycles;
  return n;
}

MemoryUse PeMemory::use() const {
  MemoryUse u;
  u.ideal = ideal();
  const std::vector<Stats> s = requesters();
  for (size_t i = 0; i < s.size(); ++i)
    u.requesters.push_back({s[i].name, s[i].requests, s[i].bytes, s[i].stall_cycles,
                            wait_cycles_[i], access_cycles_[i]});
  if (timing_) {
    for (const auto& p : timing_->ports()) u.port_busy_cycles.push_back(p.busy_cycles);
    for (const auto& b : timing_->banks()) u.bank_conflicts += b.conflicts;
  }
  u.beats = beats_;
  for (const CoefficientRam& r : coef_rams_) {
    u.coef_hits += r.hits();
    u.coef_misses += r.misses();
    u.coef_evictions += r.evictions();
  }
  if (cache_) {
    u.voxel_cache = true;
    u.cache_hits = cache_->hits();
    u.cache_misses = cache_->misses();
    u.cache_line_fills = cache_->line_fills();
  }
  return u;
}

}  // namespace rtm
