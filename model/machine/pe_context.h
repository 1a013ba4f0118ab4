// What the modules of one PE share: the configuration, the scene image in local memory, the
// counters they fill in, and the waveform window.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <systemc>

#include "machine/config.h"
#include "machine/timekeeper.h"
#include "machine/trace_window.h"
#include "render/reference.h"
#include "render/trace.h"

namespace rtm {

/// The scene data the host sends every PE (paper §3.1: primitives, voxel data, lights).
struct SceneImage {
  const Scene* scene = nullptr;
  const Grid* grid = nullptr;
  SceneMemory<float> mem32;
  SceneMemory<double> mem64;
  uint64_t bytes = 0;  ///< the size the transfer is timed by

  SceneImage(const Scene& s, const Grid& g, const MachineConfig& c);
};

/// Busy cycles and items of one unit.
struct UnitStats {
  uint64_t busy_cycles = 0;
  uint64_t items = 0;
};

struct PeCounters {
  TraceCounts counts;
  uint64_t mac_products = 0;
  uint64_t mac_products_saved = 0;  ///< skipped by sparse schedules, against the paper's 28 per test
  uint64_t mac_cycles_saved = 0;    ///< MAC busy cycles saved by sparse schedules
  uint64_t spills = 0;
  UnitStats front, search, mac, root, shade;  ///< search: summed over the replicated units
  sc_core::sc_time start = sc_core::SC_ZERO_TIME;         ///< the first primary ray handed out
  sc_core::sc_time finish = sc_core::SC_ZERO_TIME;        ///< the last ray ended
  sc_core::sc_time credit_stall = sc_core::SC_ZERO_TIME;  ///< rays waiting but no credit to send them
};

/// Busy flag and the id of the ray a unit works on, as traced variables. Outside the waveform
/// window they are left alone, so the VCD file records nothing there.
class UnitProbe {
 public:
  void begin(uint32_t ray_id) {
    if (!window_ || !window_->now()) return;
    busy_ = true;
    ray_id_ = ray_id;
  }
  void end() {
    if (window_ && window_->now()) busy_ = false;
  }
  void trace(sc_core::sc_trace_file* tf, const std::string& prefix, const TraceWindow* w) {
    window_ = w;
    sc_core::sc_trace(tf, busy_, prefix + ".busy");
    sc_core::sc_trace(tf, ray_id_, prefix + ".ray_id");
  }

 private:
  const TraceWindow* window_ = nullptr;
  bool busy_ = false;
  uint32_t ray_id_ = 0;
};

/// Which optional units a PE elaborates (all of them unless the machine leaves out what the
/// scene cannot use).
struct PeUnits {
  bool spawn_path = true;    ///< spawn FIFO from shading back to the front buffer
  bool shadow_rays = true;   ///< shading's shadow-ray generator
  bool reflection = true;    ///< shading's reflected-ray generator
  bool refraction = true;    ///< shading's transmitted-ray generator

  /// Whether shading can spawn rays of this kind.
  bool generates(RayKind k) const {
    return k == RayKind::Shadow ? shadow_rays : k == RayKind::Reflected ? reflection : refraction;
  }
};

/// Within a PE, the same-cycle order of the kinds of unit (timekeeper.h); units of one kind due
/// in the same cycle go in the order they took their work, so which of the replicated search
/// units holds a ray never matters. Root units rank by their lane (Root + lane): each takes only
/// its own MAC's results, so no work order could rank them.
enum class UnitRank { FrontBuffer, Shading, Search, Mac, Root };

struct PeContext {
  int pe = 0;
  PeUnits units;
  MachineConfig config;
  sc_core::sc_time cycle;  ///< the PE clock period
  std::shared_ptr<const SceneImage> image;  ///< set when the scene transfer lands in local memory
  PeCounters counters;
  TraceWindow window;
  uint32_t next_ray_id = 0;
  Timekeeper* keeper = nullptr;  ///< arbitration = ranked: every timed wait goes through it

  sc_core::sc_time cycles(uint64_t n) const { return cycle * double(n); }
  /// A sleeper for one more process of this PE (`lane`: a root unit's).
  std::unique_ptr<Sleeper> sleeper(UnitRank kind, int lane = 0) const {
    return std::make_unique<Sleeper>(keeper, kRanksPerPe * (pe + 1) + int(kind) + lane);
  }
  /// Waits until the next PE clock boundary (work arriving from the host is not aligned).
  void align(Sleeper& sleep) const {
    const sc_dt::uint64 now = sc_core::sc_time_stamp().value(), c = cycle.value();
    if (const sc_dt::uint64 r = now % c) sleep(sc_core::sc_time::from_value(c - r));
  }
  static constexpr int kRanksPerPe = 128;  // more than UnitRank and 64 root lanes need
};

}  // namespace rtm
