#include "machine/watchdog.h"

#include <algorithm>
#include <cstdio>

#include "machine/engine_pe.h"
#include "machine/sim_time.h"
#include "memory/memory_layout.h"
#include "memory/records.h"
#include "render/progress.h"

namespace rtm {

using sc_core::sc_time;

void ProgressDisplay::draw(const std::vector<Pe*>& pes, const Host& host) {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(500) || now - start_ < std::chrono::seconds(1))
    return;
  last_draw_ = now;
  Progress p;
  bool all_done = true;
  for (const Pe* pe : pes) {
    p.pixels_started += pe->ctx.counters.counts.rays[0];
    all_done = all_done && pe->finished();
  }
  const bool generated = host.times.rays != 0;  // the host's primary rays
  p.phase = all_done ? "gather" : p.pixels_started ? "PEs" : generated ? "transfer" : "host";
  p.pixels = pixels_;
  p.seconds = std::chrono::duration<double>(now - start_).count();
  p.resident_bytes = resident_bytes();
  std::fprintf(stderr, "\r%-79s", progress_line(p).c_str());
  std::fflush(stderr);
  drew_ = true;
}

uint64_t Watchdog::longest_item_cycles(const Scene& s, const Grid& g, const MachineConfig& c) {
  ItemBounds b;
  for (size_t v = 0; v + 1 < g.start.size(); ++v)
    b.fullest_voxel = std::max<uint64_t>(b.fullest_voxel, g.start[v + 1] - g.start[v]);
  for (const Primitive& p : s.primitives)
    b.most_clips = std::max<uint64_t>(b.most_clips, p.clips.size());
  b.lights = s.lights.size();
  b.walk_voxels = uint64_t(g.n[0] + g.n[1] + g.n[2] + 3);
  // A local-memory access at its slowest: its largest record behind one of every requester's.
  const uint64_t record = std::max<uint64_t>({kSpillRecordBytes, coef_record_bytes(Precision::Fp64),
                                              voxel_list_bytes(b.fullest_voxel + 2)});
  b.access = uint64_t(c.search_units + c.intersection_units + 3) *
             (uint64_t(c.memory_latency) + record / uint64_t(c.memory_bytes_per_cycle) + 1);
  uint64_t cycles = 0;
  for (const UnitSpec& u : unit_table()) cycles += u.longest_item(c, b);
  return cycles;
}

Watchdog::Watchdog(const Scene& s, const Grid& g, const MachineConfig& c,
                   const std::vector<Pe*>& pes, const Host& host, uint64_t max_memory,
                   uint64_t max_rays, ProgressDisplay* progress)
    : pes_(pes),
      host_(host),
      max_memory_(max_memory),
      max_rays_(max_rays),
      progress_(progress),
      active_(pes) {
  // The clock, and units retrying writes into full FIFOs, keep a simulation alive even when the
  // loop has stalled; and any frame's time must stay below the horizon: watch for both.
  const sc_time period(c.clock_ns, sc_core::SC_NS);
  // A PE on the engine shows its work a quantum at a time.
  const double quiet_cycles = std::max({8.0 * kStepCycles, 2.0 * double(EnginePe::kQuantumCycles),
                                        2.0 * double(longest_item_cycles(s, g, c))});
  quiet_window_ = sc_time::from_value(
      uint64_t(std::min(quiet_cycles * double(period.value()), double(kTimeHorizonTicks))));
  base_step_ = period * kStepCycles;
  longest_step_ = std::max(base_step_, quiet_window_ / 8.0);
}

uint64_t Watchdog::work_done(bool& over) {
  // A finished PE's counters no longer change: add them once and look at it no more.
  uint64_t work = finished_work_, rays = finished_rays_;
  for (size_t i = 0; i < active_.size();) {
    const PeCounters& k = active_[i]->ctx.counters;
    const uint64_t w = k.all().items;
    const uint64_t r = k.counts.total_rays();
    if (active_[i]->finished()) {
      finished_work_ += w;
      finished_rays_ += r;
      active_[i] = active_.back();
      active_.pop_back();
    } else {
      ++i;
    }
    work += w;
    rays += r;
  }
  if (max_rays_ && rays > max_rays_) {
    over_rays = rays;
    over = true;
  }
  return work;
}

bool Watchdog::look(sc_time& step) {
  const sc_time at = sc_core::sc_time_stamp();
  if (at.value() >= kTimeHorizonTicks) {
    overran = true;
    return false;
  }
  // Rays waiting in the front buffers grow with the ray tree: hold the process to the budget.
  if (const auto wall = std::chrono::steady_clock::now();
      max_memory_ && wall - last_measured_ > kMeasureEvery) {
    last_measured_ = wall;
    if (const uint64_t rss = resident_bytes(); rss > max_memory_) {
      over_budget = rss;
      return false;
    }
  }
  // The host's own phase (sending every PE its scene, say) is no stall: look again when it
  // ends, without summing every PE's counters on each transfer.
  const bool host_busy = at < host_.busy_until;
  uint64_t work = last_work_;
  if (!host_busy) {
    bool over = false;
    work = work_done(over);
    if (over) return false;
  }
  const bool moved = work != last_work_;
  last_work_ = work;
  if (moved) {
    quiet_since_ = at;
    step = base_step_;
  } else if (host_busy) {
    quiet_since_ = host_.busy_until;
    step = std::max(base_step_, host_.busy_until - at);
  } else if (at >= quiet_since_ && at - quiet_since_ >= quiet_window_) {
    stalled = true;
    return false;
  } else {
    step = std::min(step * 2.0, longest_step_);
  }
  if (progress_) progress_->draw(pes_, host_);
  return true;
}

}  // namespace rtm
