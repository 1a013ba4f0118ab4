// A PE's macro-pipeline on its own event loop instead of SystemC processes.
//
// The units are those the modules run (units/), with the same FIFOs (units/fifo_table.h), and the
// engine drives them in the order the modules act under `arbitration = ranked`, so every cycle
// count, statistic and event-log line comes out identical (tb/engine_test.cpp renders frames both
// ways and compares). What it saves is the kernel's context switches, events and FIFO copies on
// every one of a ray's voxel passes: a ray walks ~30 voxels, and in the modules each pass costs
// two process switches and two timed events. docs/machine.md, "The PE engine", states the order it
// reproduces; the engine itself only schedules.
//
// Time is in SystemC time-resolution units (sc_time::value()). Each unit keeps its pipeline
// (units/pipeline.h) and the wake-ups it asked for (units/wakeups.h), and every wake-up is the
// same step the modules take (units/unit_step.h). Order within one instant, as in the modules:
// first the units woken then, by UnitKind rank, units of a rank in the order they asked; each
// writes its due results and takes its next item from what its input FIFO held before the
// instant; then the items written in the instant become visible, units waiting for input take
// them (of replicated units, the lowest-numbered first), and the front buffer, if it was waiting,
// drains its inputs.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <tuple>
#include <utility>
#include <variant>
#include <vector>

#include "units/clock_level_mac.h"
#include "units/fifo_report.h"
#include "units/front_buffer.h"
#include "units/intersection.h"
#include "units/ray_stage.h"
#include "units/shading_unit.h"
#include "units/unit_step.h"
#include "units/wakeups.h"

namespace rtm {

/// Why a configuration cannot run on the engine, or "" when it can. `tracing`: a waveform is
/// requested (the engine has no signals to trace).
std::string engine_unsupported(const MachineConfig& c, bool tracing);

class PeEngine {
 public:
  /// `frame`, `ids`: the PE's frame buffer in local memory; `rays`: its primary rays, of which
  /// rays_arrived() says how many are there.
  PeEngine(PeState& pe, std::vector<PixelSum>& frame, std::vector<int32_t>& ids,
           const std::vector<Ray>& rays, size_t rays_expected);

  /// Simulates everything that happens before time t, stopping after an instant in which the PE
  /// asked for a tile (partition = dynamic: its answer may arrive before t) or ended a frame
  /// (frames > 1: the next frame's rays may arrive before t).
  void run_before(uint64_t t);
  /// The first n primary rays, of `expected` (kRaysUnknown: more may come), are in local memory
  /// from time t on (no earlier than what ran).
  void rays_arrived(uint64_t t, size_t n, size_t expected);
  size_t rays_known() const { return front_.primaries_known(); }
  /// When the PE asked for a tile in what ran last (kNever: it did not), forgetting it.
  uint64_t take_ask() { return std::exchange(asked_at_, kNever); }
  /// When the PE ended a frame, more to come, in what ran last (kNever: it did not), forgetting it.
  uint64_t take_frame_end() { return std::exchange(frame_ended_at_, kNever); }

  bool finished() const { return front_.finished(); }
  uint64_t finish_time() const { return pe_.counters.finish; }
  /// Nothing left to simulate (finished, or stalled with rays outstanding).
  bool idle() const;

  /// Every FIFO's statistics, closed at time `now`, named and ordered as the modules report them.
  FifoStatsList fifo_stats(uint64_t now, double seconds_per_tick);
  std::string occupancy_report();

  static constexpr uint64_t kNever = UINT64_MAX;

 private:
  /// The engine's two phases of an instant, numbered on by step(): first the units due, then
  /// the units taking what was written. What is written in a phase is visible from the next on, and
  /// a place a read frees is there for writers from the next phase on, as in sc_fifo.
  struct Phase {
    uint64_t number = 0;
    bool written = false;      ///< something was written in it
    bool front_input = false;  ///< ... into an input of the front buffer
  };

  /// A FIFO of ray slots (or MAC results, or ray ids), each item stamped with the phase it was
  /// written in. Metered as MeteredFifo is.
  struct Fifo {
    std::string name;
    size_t depth;
    std::vector<uint32_t> ring;     ///< `depth` places; items from `head`, `count` of them
    std::vector<uint64_t> written;  ///< the phase each place's item was written in
    size_t head = 0, count = 0;
    uint64_t read_phase = 0;  ///< the phase of the last read ...
    size_t reads = 0;         ///< ... and the reads in it
    FifoMeter meter;
    bool feeds_front = false;  ///< an input of the front buffer: a write wakes it
    Phase* phase;

    Fifo(const FifoSpec& spec, int depth, Phase* phase);
    /// An item for readers: written before this phase.
    bool visible() const { return count > 0 && written[head] < phase->number; }
    void write(uint32_t v, uint64_t now) {
      size_t at = head + count++;
      at = at < depth ? at : at - depth;
      ring[at] = v;
      written[at] = phase->number;
      phase->written = true;
      phase->front_input = phase->front_input || feeds_front;
      meter.change(+1, now);
    }
    uint32_t read(uint64_t now) {
      const uint32_t v = ring[head];
      head = head + 1 == depth ? 0 : head + 1;
      --count;
      reads = read_phase == phase->number ? reads + 1 : 1;
      read_phase = phase->number;
      meter.change(-1, now);
      return v;
    }
    /// No room to write in this phase (sc_fifo::num_free() == 0).
    bool full() const { return count + (read_phase == phase->number ? reads : 0) >= depth; }
  };

  /// What a unit holds in its pipeline: a ray slot (front buffer, search units, shading) or a MAC
  /// result (MACs, root units), and where a search, MAC or root unit's result goes.
  struct Held {
    uint32_t item = 0;
    Output out;
  };
  /// A unit: its pipeline, the wake-ups it asked for, and whether it waits for input.
  struct Place {
    Pipeline<Held> pipe;
    Wakeups wakeups;
    uint64_t order =
        0;  ///< its earliest wake-up (due_at_) ranked: the unit's rank, then when it asked
    bool waiting = false;  ///< a root unit's or shading's wait for input
    UnitKind kind;
    int index;      ///< among the units of its kind
    uint64_t rank;  ///< its same-instant rank, shifted into `order`
    Place(uint64_t cycle, UnitStats* stats, UnitKind k, int i)
        : pipe(cycle, stats),
          kind(k),
          index(i),
          rank(uint64_t(k) + (unit_spec(k).ranked_by_lane ? uint64_t(i) : 0)) {}
    /// Its order for a wake-up it asked for as the seq-th: by rank, then by when it asked.
    uint64_t ranked(uint64_t seq) const { return rank << 48 | seq; }
  };
  template <UnitKind K>
  struct Ops;         // a kind of unit's operations for step_unit (units/unit_step.h)
  struct FrontOps;    // the front buffer's for FrontBufferPolicy::carry_out
  struct ShadingOps;  // shading's for ShadingWriter

  /// The place of unit `index` of kind k: places are in the unit table's order, each kind's by
  /// number.
  size_t place(UnitKind k, size_t index = 0) const { return first_place_[size_t(k)] + index; }

  /// The next instant, with the units due then in due_now_ (due_count_ of them).
  uint64_t next_instant();
  void step(uint64_t now);
  void next_phase();
  void want(size_t unit, uint64_t at);
  /// Wakes a unit (units/unit_step.h).
  void wake(size_t unit, uint64_t now);
  void take_inputs(uint64_t now);
  Fifo& fifo(FifoId id, size_t lane = 0) { return fifos_[first_fifo_[size_t(id)] + lane]; }

  uint32_t new_ray(const MachineRay& r);
  /// Clocked timing: MAC `lane` took the job of `m`, which the fast model times at `cycles`; ...
  void clocked_job(size_t lane, const MacResult& m, uint64_t cycles, uint64_t now);
  /// ... its result `result` is due, and its FIFO is `full` or not.
  void clocked_result(size_t lane, uint32_t result, bool full, uint64_t now);
  /// Writes a search or root unit's output for ray `r` (held in `slot`, or kNoSlot: in a MAC
  /// result); false when its FIFO is full.
  bool emit(const Output& o, const MachineRay& r, uint32_t slot, UnitKind kind, int index,
            uint64_t now);
  static constexpr uint32_t kNoSlot = UINT32_MAX;

  PeState& pe_;
  std::vector<PixelSum>& frame_;
  std::vector<int32_t>& ids_;
  const std::vector<Ray>& rays_;
  const uint64_t cycle_;

  std::vector<MachineRay> slots_;  ///< rays in the loop
  std::vector<uint32_t> free_slots_;
  std::vector<MacResult> results_;  ///< MAC results on their way to the root unit
  std::vector<uint32_t> free_results_;

  Phase phase_;
  /// The PE's FIFOs as for_each_fifo (units/fifo_report.h) lists them; each FIFO's first (a
  /// per-lane FIFO's lanes follow it).
  std::vector<Fifo> fifos_;
  std::array<size_t, kFifoCount> first_fifo_{};
  /// The front buffer's ray inputs, in the table's order, and whether each returns a credit.
  std::vector<std::pair<Fifo*, bool>> front_inputs_;

  std::vector<Place> places_;
  std::array<size_t, kUnitKinds> first_place_{};
  std::vector<uint64_t>
      due_at_;  ///< each place's earliest wake-up (kNever: none), packed: scanned every instant
  std::vector<size_t> due_now_;  ///< the first due_count_ are the units due at the next instant
  size_t due_count_ = 0;
  uint64_t seq_ = 0;
  uint64_t pending_step_ = kNever;    ///< an instant with no unit due but rays arriving
  bool front_poked_ = false;          ///< an input of the front buffer was written in this instant
  uint64_t asked_at_ = kNever;        ///< the PE asked for a tile then
  uint64_t frame_ended_at_ = kNever;  ///< the PE ended a frame then (frames > 1)

  // The units.
  FrontBufferPolicy<uint32_t> front_;
  /// The ray stages' units (units/ray_stage.h), a vector per kind.
  /// (std::monostate only starts the list.)
#define RTM_RAY_STAGE_UNITS(kind, Class) , std::vector<Class>
  std::tuple<std::monostate RTM_RAY_STAGES(RTM_RAY_STAGE_UNITS)> stage_units_;
#undef RTM_RAY_STAGE_UNITS
  template <UnitKind K>
  std::vector<typename RayStage<K>::Unit>& stage_units() {
    return std::get<std::vector<typename RayStage<K>::Unit>>(stage_units_);
  }
  std::array<Fifo*, kUnitKinds> stage_input_{};  ///< a ray stage's input FIFO
  std::vector<MacUnit> macs_;
  std::vector<EdgeByEdgeMac> clocked_macs_;  ///< per MAC, in clocked timing only
  std::vector<RootUnit> roots_;
  ShadingUnit shading_;
  /// By kind, the replicated units (ray stages, MACs) waiting for an item: the lowest-numbered
  /// takes it.
  std::array<LaneDispatcher, kUnitKinds> waiting_;
  ShadingWriter<uint32_t> shading_writer_;
};

}  // namespace rtm
