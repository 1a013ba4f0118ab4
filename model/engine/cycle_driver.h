// A second driver of a PE's units, for the PE engine's tests only: the plainest loop that follows
// units/unit_step.h's contract and the order the engine states (engine/pe_engine.h), with none
// of the engine's shortcuts. Every PE cycle, in this order:
//  1. each unit with a wake-up at this cycle steps (step_unit), by rank (UnitKind, a root unit's
//     lane added), units of one rank in the order they asked;
//  2. what they wrote becomes visible; every unit waiting for input whose input holds an item
//     steps, the ray stages, MACs and root units in rank order and units of a kind by number,
//     then shading (the modules' order, which the engine follows); then the front buffer steps
//     if it waits for input and one of its inputs was written (or the rays arrived);
//  3. places freed by reads become free for the next cycle's writers.
// FIFOs are plain queues of whole items, each stamped with the step in which it was written: an
// item is visible from the next step on, and a place read in a step is free from the next one,
// as in sc_fifo. Every wake-up a unit asks for must fall on a PE clock edge (the loop visits no
// other time). pe_engine_test.cpp runs hand-built frames on both and compares the event logs.
#pragma once

#include <algorithm>
#include <deque>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "units/fifo_report.h"
#include "units/front_buffer.h"
#include "units/intersection.h"
#include "units/ray_stage.h"
#include "units/shading_unit.h"
#include "units/unit_step.h"
#include "units/wakeups.h"

namespace rtm {

class CycleDriver {
 public:
  /// `frame`, `ids`: the PE's frame buffer; `rays`: its primary rays, all there at cycle 0.
  CycleDriver(PeState& pe, std::vector<PixelSum>& frame, std::vector<int32_t>& ids,
              const std::vector<Ray>& rays)
      : pe_(pe), frame_(frame), ids_(ids), rays_(rays), front_(pe, rays.size()), shading_(pe) {
    for_each_fifo(pe, [&](const FifoSpec& f, int lane) {
      if (lane == 0) first_fifo_[size_t(f.id)] = fifos_.size();
      fifos_.push_back({size_t(pe.config.*f.depth), {}, {}, 0, 0});
    });
    for (const UnitSpec& s : unit_table())
      for (int i = 0, n = unit_count(s.kind, pe.config); i < n; ++i)
        units_.push_back(
            {s.kind, i, Pipeline<Held>(pe.cycle, &pe.counters.unit(s.kind, i)), {}, false, -1});
    for_each_ray_stage([&](auto kind) {
      using Class = typename RayStage<kind()>::Unit;
      for (Unit& u : units_)
        if (u.kind == kind()) {
          u.stage = int(stage_take_.size());
          stage_take_.emplace_back([c = Class(pe, u.index)](MachineRay& r, uint64_t now) mutable {
            return c.take(r, now);
          });
        }
    });
    for (int i = 0, n = unit_count(UnitKind::Mac, pe.config); i < n; ++i) macs_.emplace_back(pe, i);
    for (int i = 0, n = unit_count(UnitKind::Root, pe.config); i < n; ++i)
      roots_.emplace_back(pe, i);
  }

  /// Runs the frame until no unit asks for a wake-up, at most `max_cycles`; returns whether the
  /// front buffer finished.
  bool run(uint64_t max_cycles) {
    for (Unit& u : units_) step(u, 0);
    front_.primaries_arrived(rays_.size());
    front_written_ = true;
    for (uint64_t cycle = 0; cycle < max_cycles; ++cycle) {
      const uint64_t now = cycle * pe_.cycle;
      // 1. The units due now, ranked.
      std::vector<std::pair<uint64_t, Unit*>> due;
      for (Unit& u : units_) {
        const auto [at, order] = u.wakeups.next();
        if (at < now) throw std::logic_error("CycleDriver: a wake-up missed");
        if (at == now) due.push_back({rank(u) << 48 | order, &u});
      }
      std::sort(due.begin(), due.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      for (auto& [order, u] : due) {
        u->wakeups.fired(now);
        step(*u, now);
      }
      // 2. Written items are visible; the units waiting for input take them.
      const bool poked = front_written_;
      front_written_ = false;
      ++phase_;
      for (Unit& u : units_)
        if (u.kind != UnitKind::FrontBuffer && u.kind != UnitKind::Shading && u.waiting &&
            visible(input(u)))
          step(u, now);
      if (Unit& u = shading(); u.waiting && visible(input(u))) step(u, now);
      if (front_.waiting_for_input() && poked) step(front(), now);
      // 3. Freed places are free.
      ++phase_;
      if (std::all_of(units_.begin(), units_.end(),
                      [](const Unit& u) { return u.wakeups.empty(); }))
        break;
    }
    return front_.finished();
  }

 private:
  /// What a unit holds: the ray (m.r) or the MAC result, and where its result goes.
  struct Held {
    MacResult m;
    Output out;
  };
  struct Unit {
    UnitKind kind;
    int index;
    Pipeline<Held> pipe;
    Wakeups wakeups;
    bool waiting = false;  ///< waits for input (all but the front buffer, whose policy knows)
    int stage = -1;        ///< a ray stage's: its place in stage_take_
  };
  /// A FIFO of whole items (a ray's end: its id in m.r.id).
  struct Fifo {
    size_t depth;
    std::deque<MacResult> items;
    std::deque<uint64_t> written;  ///< the phase each item was written in
    uint64_t read_phase, reads;    ///< the phase of the last read, and the reads in it
  };

  static uint64_t rank(const Unit& u) {
    return uint64_t(u.kind) + (unit_spec(u.kind).ranked_by_lane ? uint64_t(u.index) : 0);
  }
  // The front buffer and shading rank first.
  Unit& front() { return units_[0]; }
  Unit& shading() { return units_[1]; }
  Fifo& fifo(FifoId id, int lane = 0) { return fifos_[first_fifo_[size_t(id)] + size_t(lane)]; }
  /// A unit's one input (not the front buffer's: it drains several).
  Fifo& input(const Unit& u) {
    return fifo(inputs(u.kind).front(), fifo_spec(inputs(u.kind).front()).per_lane ? u.index : 0);
  }
  bool visible(const Fifo& f) const { return !f.items.empty() && f.written.front() < phase_; }
  bool full(const Fifo& f) const {
    return f.items.size() + (f.read_phase == phase_ ? f.reads : 0) >= f.depth;
  }
  bool read(Fifo& f, MacResult& out) {
    if (!visible(f)) return false;
    out = std::move(f.items.front());
    f.items.pop_front();
    f.written.pop_front();
    f.reads = f.read_phase == phase_ ? f.reads + 1 : 1;
    f.read_phase = phase_;
    return true;
  }
  /// Writes unit u's output `o` of ray (or MAC result) v; false when its FIFO is full.
  bool write(const Unit& u, const Output& o, const MacResult& v, uint64_t now) {
    Fifo& f = fifo(o.fifo, fifo_spec(o.fifo).per_lane ? u.index : 0);
    if (full(f)) return false;
    f.items.push_back(v);
    f.written.push_back(phase_);
    const std::vector<UnitKind>& readers = fifo_spec(o.fifo).readers;
    front_written_ =
        front_written_ || std::count(readers.begin(), readers.end(), UnitKind::FrontBuffer);
    record_put(pe_, now, u.kind, u.index, v.r, o);
    return true;
  }
  static MacResult of(const MachineRay& r) {
    MacResult m;
    m.r = r;
    return m;
  }

  /// Unit u's operations for step_unit, each kind's in one switch.
  struct Ops {
    CycleDriver& d;
    Unit& u;
    uint64_t now;

    void woke(uint64_t) {
      if (u.kind == UnitKind::FrontBuffer) d.front_.woke(now);
      u.waiting = false;
    }
    bool write_head(uint64_t) {
      const Held& h = u.pipe.head().item;
      switch (u.kind) {
        case UnitKind::FrontBuffer:
          return d.write(u, {FifoId::Search, Output::What::Item}, h.m, now);
        case UnitKind::Shading: {
          WriteOps ops{d, u, h.m.r, now};
          return d.writer_.write(d.shading_, ops);
        }
        default:  // a ray stage, a MAC (its result), a root unit
          return d.write(u, h.out, h.m, now);
      }
    }
    void retired(const Held&) {
      if (u.kind != UnitKind::Shading) return;
      d.shading_.retired();
      d.writer_.retired();
    }
    bool accept(uint64_t) {
      if (u.kind == UnitKind::FrontBuffer) {
        FrontOps ops{d, u, now};
        return d.front_.carry_out(now, d.pe_.cycle, ops);
      }
      Held h;
      if (!d.read(d.input(u), h.m)) return false;
      Work w;
      if (u.kind == UnitKind::Shading)
        w = d.shading_.take(h.m.r, d.frame_[h.m.r.slot], d.ids_[h.m.r.slot], now);
      else if (u.kind == UnitKind::Mac)
        w = d.macs_[size_t(u.index)].take(h.m, now);
      else if (u.kind == UnitKind::Root)
        w = d.roots_[size_t(u.index)].take(h.m, now);
      else
        w = d.stage_take_[size_t(u.stage)](h.m.r, now);
      h.out = w.out;
      u.pipe.accept(h, now, w.cycles, w.interval, std::move(w.wait));
      return true;
    }
    bool wait_for_input() {
      if (u.kind == UnitKind::FrontBuffer) return d.front_.wait(now);
      u.waiting = true;
      return true;
    }
    void want(uint64_t t) { d.want(u, t); }
  };
  /// The front buffer's operations for FrontBufferPolicy::carry_out.
  struct FrontOps {
    CycleDriver& d;
    Unit& u;
    uint64_t now;

    bool read_end() {
      MacResult end;
      return d.read(d.fifo(FifoId::Ends), end);
    }
    bool read(FifoId id, MachineRay& r) {
      MacResult m;
      if (!d.read(d.fifo(id), m)) return false;
      r = m.r;
      return true;
    }
    void drained() {}
    MachineRay primary(size_t n) { return primary_ray(d.pe_, d.rays_, n); }
    void dispatch(MachineRay&& r, uint64_t cycles, uint8_t from, MemoryWait&& wait) {
      d.front_.dispatched(now, r.id, cycles, from);
      u.pipe.accept({of(r), {}}, now, cycles, d.front_.interval(cycles), std::move(wait));
    }
    void want(uint64_t t) { d.want(u, t); }
    void finished() {}
    void ask_for_tile() {}  // it holds every primary ray from the start
    void frame_ended() {}   // and runs one frame
  };
  /// Shading's operations for ShadingWriter: `ray` is the oldest shaded ray.
  struct WriteOps {
    CycleDriver& d;
    Unit& u;
    const MachineRay& ray;
    uint64_t now;

    bool write_end(const Output& o) { return d.write(u, o, of(ray), now); }
    MachineRay make(size_t k) { return d.shading_.spawn(ray, k); }
    bool write(const Output& o, const MachineRay& child) { return d.write(u, o, of(child), now); }
  };

  void step(Unit& u, uint64_t now) {
    Ops ops{*this, u, now};
    step_unit(u.pipe, now, pe_.cycle, pe_.memory.get(), ops);
  }
  void want(Unit& u, uint64_t t) {
    if (t % pe_.cycle)
      throw std::logic_error("CycleDriver: a wake-up between clock edges, at tick " +
                             std::to_string(t));
    u.wakeups.want(t, seq_++);
  }

  PeState& pe_;
  std::vector<PixelSum>& frame_;
  std::vector<int32_t>& ids_;
  const std::vector<Ray>& rays_;
  std::vector<Fifo> fifos_;
  std::array<size_t, kFifoCount> first_fifo_{};
  std::vector<Unit> units_;  ///< in rank order, a kind's by number
  uint64_t phase_ = 1, seq_ = 0;
  bool front_written_ = false;  ///< an input of the front buffer was written in this cycle

  FrontBufferPolicy<MachineRay> front_;
  std::vector<std::function<Work(MachineRay&, uint64_t)>> stage_take_;  ///< every ray stage's
  std::vector<MacUnit> macs_;
  std::vector<RootUnit> roots_;
  ShadingUnit shading_;
  ShadingWriter<MachineRay> writer_;
};

}  // namespace rtm
