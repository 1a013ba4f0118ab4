// A PE's macro-pipeline on its own event loop instead of SystemC processes.
//
// The units, FIFOs, routing and work are those of the modules in pe.h (unit_work.h), and they act
// in the order the modules act under `arbitration = ranked`, so every cycle count and statistic
// comes out identical (tb/engine_test.cpp renders frames both ways and compares). What it saves is
// the kernel's context switches, events and FIFO copies on every one of a ray's voxel passes: a
// ray walks ~30 voxels, and in the modules each pass costs two process switches and two timed
// events. docs/machine.md, "The PE engine", states the order it reproduces.
//
// Time is in SystemC time-resolution units (sc_time::value()). Order within one instant, as in
// the modules: first the units whose work ends then, by UnitRank, units of a rank in the order
// they took their work; each writes its result and takes its next item from what its input FIFO
// held before the instant; then the items written in the instant become visible, idle units take
// them, and the front buffer, if it was waiting, drains its inputs.
#pragma once

#include <cstdint>
#include <deque>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "machine/metered_fifo.h"
#include "machine/unit_work.h"

namespace rtm {

/// Why a configuration cannot run on the engine, or "" when it can. `tracing`: a waveform is
/// requested (the engine has no signals to trace).
std::string engine_unsupported(const MachineConfig& c, bool tracing);

class PeEngine {
 public:
  /// `frame`, `ids`: the PE's frame buffer in local memory; `rays`: its primary rays, of which
  /// rays_arrived() says how many are there.
  PeEngine(PeContext& ctx, std::vector<PixelSum>& frame, std::vector<int32_t>& ids, const std::vector<Ray>& rays,
           size_t rays_expected);

  /// Simulates everything that happens before time t.
  void run_before(uint64_t t);
  /// The first n primary rays are in local memory from time t on (no earlier than what ran).
  void rays_arrived(uint64_t t, size_t n);
  size_t rays_known() const { return rays_visible_; }

  bool finished() const { return front_ == Front::Done; }
  uint64_t finish_time() const { return finish_; }
  /// Nothing left to simulate (finished, or stalled with rays outstanding).
  bool idle() const;

  /// Every FIFO's statistics, closed at time `now`, named as the modules name them.
  std::vector<std::pair<std::string, const FifoStats*>> fifo_stats(uint64_t now);
  std::string occupancy_report() const;

 private:
  static constexpr uint64_t kNever = UINT64_MAX;

  /// A FIFO of ray slots (or MAC results); items written in the current instant are not yet
  /// visible to readers. Metered as MeteredFifo is.
  struct Fifo {
    std::string name;
    std::vector<uint32_t> ring;  ///< `depth` places; items from `head`, `count` of them
    size_t head = 0, count = 0;
    size_t visible = 0;
    bool written = false;  ///< in the current instant
    size_t reads_now = 0;  ///< in the current instant: places freed only once it is over
    FifoMeter meter;

    bool touched = false;  ///< written or read in the current instant: on the touched list
    std::vector<Fifo*>* touched_list;

    Fifo(std::string n, const char* kind, int depth, std::vector<Fifo*>* touched_list);
    void touch() {
      if (!touched) touched_list->push_back(this);
      touched = true;
    }
    void write(uint32_t v, uint64_t now) {
      ring[(head + count++) % ring.size()] = v;
      written = true;
      touch();
      meter.change(+1, now);
    }
    uint32_t read(uint64_t now) {
      const uint32_t v = ring[head];
      head = head + 1 == ring.size() ? 0 : head + 1;
      --count;
      --visible;
      ++reads_now;
      touch();
      meter.change(-1, now);
      return v;
    }
    /// No room to write in this instant (sc_fifo::num_free() == 0).
    bool full() const { return count + reads_now >= ring.size(); }
  };

  enum class Unit : uint8_t { FrontBuffer, Shading, Search, Mac, Root };
  /// A unit's pending wake-up: its work (or its wait for room in a full FIFO) ends at due_at_.
  /// One per unit: a few units, so a scan finds the next instant faster than a heap would.
  struct Due {
    uint64_t order = 0;        ///< the unit's rank, then (units of one rank due together) when it took its work
    uint32_t item = 0;         ///< a search unit's ray slot; a MAC's or root unit's MAC result
    Route route = Route::End;  ///< a search or root unit's route
  };
  // Places in due_: the front buffer, shading, then the search units, the MACs and the root units.
  static constexpr size_t kFront = 0, kShading = 1, kSearch = 2;
  Unit unit_at(size_t place) const {
    return place >= root0_ ? Unit::Root : place >= mac0_ ? Unit::Mac : place >= kSearch ? Unit::Search
         : place == kFront ? Unit::FrontBuffer : Unit::Shading;
  }

  /// The next instant, with the units due then in due_now_.
  uint64_t next_instant();
  void step(uint64_t now);
  void schedule(size_t unit, uint64_t at, uint32_t item = 0, Route route = Route::End);
  void wake(size_t unit, const Due& d, uint64_t now);
  void take_inputs(uint64_t now);

  uint32_t new_ray(const MachineRay& r);
  void end_ray(uint32_t slot, uint64_t now);

  void front_loop(uint64_t now);
  void primary(uint64_t now);
  void dispatch(uint32_t slot, uint64_t cycles, uint64_t now);
  void search_start(size_t unit, uint32_t slot, uint64_t now);
  void mac_start(size_t lane, uint32_t slot, uint64_t now);
  void root_start(size_t lane, uint32_t result, uint64_t now);
  void shade_start(uint32_t slot, uint64_t now);

  PeContext& ctx_;
  std::vector<PixelSum>& frame_;
  std::vector<int32_t>& ids_;
  const std::vector<Ray>& rays_;
  const size_t rays_expected_;
  const uint64_t cycle_;
  const int credits_;
  const MacTiming timing_;

  std::vector<MachineRay> slots_;  ///< rays in the loop
  std::vector<uint32_t> free_slots_;
  std::vector<MacResult> results_;  ///< MAC results on their way to the root unit
  std::vector<uint32_t> free_results_;

  std::vector<Fifo*> touched_;  ///< FIFOs written or read in the current instant
  Fifo search_fifo_, intersect_fifo_, shade_fifo_, feedback_search_, feedback_intersect_, spawn_fifo_, ends_fifo_;
  std::deque<Fifo> to_root_;  ///< one per intersection unit (a deque: the FIFOs must not move)
  const bool spawn_path_;
  std::vector<Fifo*> fifos_;  ///< in the order fifo_stats reports them

  std::vector<uint64_t> due_at_;  ///< kNever: not due, the unit is idle
  std::vector<Due> due_;
  std::vector<size_t> due_now_;
  uint64_t seq_ = 0;
  uint64_t pending_step_ = kNever;  ///< an instant with no unit due but rays arriving
  bool front_poked_ = false;        ///< an input of the front buffer was written in this instant

  // Front buffer
  enum class Front : uint8_t { Waiting, Dispatching, Aligning, Done } front_ = Front::Waiting;
  std::deque<uint32_t> queue_;
  uint32_t front_ray_ = 0;
  size_t next_primary_ = 0, rays_visible_ = 0;
  int in_flight_ = 0;
  bool stalled_ = false;
  uint64_t waiting_since_ = 0;

  // The other units
  const size_t lanes_, mac0_, root0_;  ///< intersection units; where their MACs and root units sit in due_
  std::vector<size_t> idle_search_;    ///< places in due_
  std::set<size_t> idle_macs_;         ///< lanes; a ray goes to the lowest idle one (LaneDispatcher)
  uint32_t shade_ray_ = 0;
  std::vector<uint32_t> clips_;
  ShadeOut shade_out_;
  size_t shade_next_ = 0;  ///< the shading unit's next write: 0 the ray's end, then each spawned ray
  uint32_t shade_child_ = 0;
  bool shade_child_made_ = false;

  uint64_t finish_ = 0;
};

}  // namespace rtm
