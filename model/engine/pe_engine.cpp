#include "engine/pe_engine.h"

#include <algorithm>
#include <stdexcept>

namespace rtm {

std::string engine_unsupported(const MachineConfig& c, bool tracing) {
  if (c.pe_simulation == MachineConfig::PeSimulation::Modules) return "pe_simulation = modules";
  if (c.arbitration != MachineConfig::Arbitration::Ranked)
    return "arbitration = kernel leaves the same-cycle order to SystemC";
  if (c.flow_control != FlowControl::Credits)
    return "flow_control = none can deadlock, which the modules report";
  if (c.dda_step_cycles == 0 || c.shade_cycles == 0 || c.accumulate_cycles == 0)
    return "a unit taking zero cycles acts within the instant it started";
  if (tracing) return "a waveform traces the modules' signals";
  return "";
}

PeEngine::Fifo::Fifo(const FifoSpec& spec, int depth, Phase* phase)
    : name(spec.name),
      depth(size_t(depth)),
      ring(size_t(depth)),
      written(size_t(depth)),
      meter(spec.kind, depth),
      phase(phase) {}

PeEngine::PeEngine(PeState& pe, std::vector<PixelSum>& frame, std::vector<int32_t>& ids,
                   const std::vector<Ray>& rays, size_t rays_expected)
    : pe_(pe),
      frame_(frame),
      ids_(ids),
      rays_(rays),
      cycle_(pe.cycle),
      front_(pe, rays_expected),
      shading_(pe) {
  for_each_fifo(pe, [&](const FifoSpec& f, int lane) {
    if (lane == 0) first_fifo_[size_t(f.id)] = fifos_.size();
    Fifo& fifo = fifos_.emplace_back(f, pe.config.*f.depth, &phase_);
    fifo.feeds_front = std::count(f.readers.begin(), f.readers.end(), UnitKind::FrontBuffer) > 0;
  });
  for (const FifoSpec& f : fifo_table())  // their places no longer move
    if (pe.units.has(f) && f.payload == Payload::Ray && !f.per_lane && fifo(f.id).feeds_front)
      front_inputs_.emplace_back(&fifo(f.id), f.returns_credit);
  for (const UnitSpec& u : unit_table()) {
    first_place_[size_t(u.kind)] = places_.size();
    for (int i = 0, n = unit_count(u.kind, pe.config); i < n; ++i)
      places_.emplace_back(cycle_, &pe.counters.unit(u.kind, i), u.kind, i);
  }
  due_at_.assign(places_.size(), kNever);
  due_now_.assign(places_.size(), 0);
  for_each_ray_stage([&](auto kind) {
    constexpr UnitKind K = kind;
    stage_input_[size_t(K)] = &fifo(inputs(K).front());
    for (int k = 0; k < unit_count(K, pe.config); ++k) stage_units<K>().emplace_back(pe, k);
  });
  for (int lane = 0; lane < unit_count(UnitKind::Mac, pe.config); ++lane) {
    macs_.emplace_back(pe, lane);
    if (pe.config.timing == Timing::Clocked)
      clocked_macs_.emplace_back(macs_.back().timing(), pe.config.intersection_precision_in_force(),
                                 cycle_);
  }
  for (int lane = 0; lane < unit_count(UnitKind::Root, pe.config); ++lane)
    roots_.emplace_back(pe, lane);
  for (size_t u = 0; u < places_.size(); ++u) wake(u, 0);
}

// ---- the event loop ----

uint64_t PeEngine::next_instant() {
  uint64_t next = pending_step_;
  size_t n = 0;  // due_now_ holds a place for every unit: no bounds to check
  const uint64_t* due = due_at_.data();
  for (size_t u = 0, units = due_at_.size(); u < units; ++u) {
    const uint64_t at = due[u];
    if (at > next) continue;
    if (at < next) {
      next = at;
      n = 0;
    }
    due_now_[n++] = u;
  }
  due_count_ = next == kNever ? 0 : n;
  return next;
}

bool PeEngine::idle() const {
  return pending_step_ == kNever &&
         std::all_of(due_at_.begin(), due_at_.end(), [](uint64_t at) { return at == kNever; });
}

void PeEngine::run_before(uint64_t t) {
  for (uint64_t next;
       asked_at_ == kNever && frame_ended_at_ == kNever && (next = next_instant()) < t;)
    step(next);
}

void PeEngine::rays_arrived(uint64_t t, size_t n, size_t expected) {
  front_.primaries_arrived(n, expected);
  front_poked_ = true;
  pending_step_ = t;
}

inline void PeEngine::want(size_t unit, uint64_t at) {
  Place& p = places_[unit];
  if (!p.wakeups.want(at, seq_)) return;
  // A new time is the earliest only if it is earlier (a time already asked for is not new).
  if (at < due_at_[unit]) {
    due_at_[unit] = at;
    p.order = p.ranked(seq_);
  }
  ++seq_;
}

void PeEngine::step(uint64_t now) {
  if (pending_step_ == now) pending_step_ = kNever;
  // The units due now (found by next_instant), in rank order.
  for (size_t i = 1; i < due_count_; ++i)  // a few at most: insertion sort
    for (size_t j = i; j > 0 && places_[due_now_[j]].order < places_[due_now_[j - 1]].order; --j)
      std::swap(due_now_[j], due_now_[j - 1]);
  for (size_t k = 0; k < due_count_; ++k) {
    const size_t u = due_now_[k];
    // Its next wake-up, ranked. Root units go by their lane: each takes only its own MAC's
    // results, and the modules rank them so (machine/pe_context.h).
    Place& p = places_[u];
    const auto [at, seq] = p.wakeups.fire(now);
    due_at_[u] = at;
    p.order = p.ranked(seq);
    wake(u, now);
  }
  // What they wrote becomes visible in the next phase. The front buffer is poked by a write to
  // any of its inputs.
  const bool poked = front_poked_ || phase_.front_input, written = phase_.written;
  front_poked_ = false;
  next_phase();
  // Units waiting for input take it, and the front buffer, if it was waiting, drains its inputs.
  // A unit waits only after finding its input empty, and what is visible grows only here, by what
  // was written: with nothing written in the instant no waiting unit has an input to take.
  if (written) take_inputs(now);
  if (front_.waiting_for_input() && poked) wake(place(UnitKind::FrontBuffer), now);
  // Places freed by reads are there for the next instant's writers.
  next_phase();
}

void PeEngine::next_phase() {
  ++phase_.number;
  phase_.written = phase_.front_input = false;
}

void PeEngine::take_inputs(uint64_t now) {
  // Replicated units: the lowest-numbered waiting one takes each ray.
  for_each_ray_stage([&](auto kind) {
    LaneDispatcher& waiting = waiting_[size_t(kind())];
    for (Fifo& in = *stage_input_[size_t(kind())]; waiting.any_idle() && in.visible();)
      wake(place(kind, size_t(waiting.take())), now);
  });
  Fifo& mac_in = fifo(FifoId::Intersect);
  LaneDispatcher& waiting_macs = waiting_[size_t(UnitKind::Mac)];
  while (waiting_macs.any_idle() && mac_in.visible())
    wake(place(UnitKind::Mac, size_t(waiting_macs.take())), now);
  for (size_t lane = 0; lane < roots_.size(); ++lane)
    if (places_[place(UnitKind::Root, lane)].waiting && fifo(FifoId::Root, lane).visible())
      wake(place(UnitKind::Root, lane), now);
  if (places_[place(UnitKind::Shading)].waiting && fifo(FifoId::Shade).visible())
    wake(place(UnitKind::Shading), now);
}

// ---- rays ----

uint32_t PeEngine::new_ray(const MachineRay& r) {
  if (free_slots_.empty()) {
    slots_.push_back(r);
    return uint32_t(slots_.size() - 1);
  }
  const uint32_t s = free_slots_.back();
  free_slots_.pop_back();
  slots_[s] = r;
  return s;
}

[[gnu::always_inline]] inline bool PeEngine::emit(const Output& o, const MachineRay& r,
                                                  uint32_t slot, UnitKind kind, int index,
                                                  uint64_t now) {
  Fifo& f = fifo(o.fifo);
  if (f.full()) return false;
  const uint32_t id = r.id;
  if (o.what == Output::What::End) {
    f.write(id, now);
    if (slot != kNoSlot) free_slots_.push_back(slot);
  } else {
    f.write(slot != kNoSlot ? slot : new_ray(r), now);
  }
  record_put(pe_, now, kind, index, r, o);
  return true;
}

// ---- the units: step_unit (units/unit_step.h) with each kind's operations ----

template <UnitKind K>
struct PeEngine::Ops {
  PeEngine& e;
  size_t u;
  uint64_t now;

  Place& place;

  Pipeline<Held>& pipe() { return place.pipe; }
  const Held& head() { return pipe().head().item; }
  int index() const { return place.index; }

  void woke(uint64_t) {
    // Whatever woke it, a unit decides again whether it waits for input.
    if constexpr (K == UnitKind::FrontBuffer) {
      e.front_.woke(now);
    } else if constexpr (RayStage<K>::value || K == UnitKind::Mac) {
      e.waiting_[size_t(K)].busy(index());
    } else {
      place.waiting = false;
    }
  }

  bool write_head(uint64_t) {
    const Held& h = head();
    if constexpr (K == UnitKind::FrontBuffer) {
      return e.emit({FifoId::Search, Output::What::Item}, e.slots_[h.item], h.item,
                    UnitKind::FrontBuffer, 0, now);
    } else if constexpr (RayStage<K>::value) {
      return e.emit(h.out, e.slots_[h.item], h.item, K, index(), now);
    } else if constexpr (K == UnitKind::Mac) {
      Fifo& out = e.fifo(FifoId::Root, size_t(index()));
      if (!e.clocked_macs_.empty()) e.clocked_result(size_t(index()), h.item, out.full(), now);
      if (out.full()) return false;
      out.write(h.item, now);
      record_put(e.pe_, now, UnitKind::Mac, index(), e.results_[h.item].r, h.out);
      return true;
    } else if constexpr (K == UnitKind::Root) {
      return e.emit(h.out, e.results_[h.item].r, kNoSlot, UnitKind::Root, index(), now);
    } else {
      ShadingOps ops{e, h.item, now};
      return e.shading_writer_.write(e.shading_, ops);
    }
  }

  void retired(const Held& h) {
    // What leaves a unit frees what it held: a shaded ray's slot, a root unit's MAC result.
    if constexpr (K == UnitKind::Shading) {
      e.free_slots_.push_back(h.item);
      e.shading_.retired();
      e.shading_writer_.retired();
    } else if constexpr (K == UnitKind::Root) {
      e.free_results_.push_back(h.item);
    } else if constexpr (K == UnitKind::Mac) {
      if (!e.clocked_macs_.empty()) e.clocked_macs_[size_t(index())].retired();
    }
  }

  bool accept(uint64_t) {
    if constexpr (K == UnitKind::FrontBuffer) {
      FrontOps ops{e, now};
      return e.front_.carry_out(now, e.cycle_, ops);
    } else if constexpr (RayStage<K>::value) {
      Fifo& in = *e.stage_input_[size_t(K)];
      if (!in.visible()) return false;
      const uint32_t slot = in.read(now);
      Work w = e.stage_units<K>()[size_t(index())].take(e.slots_[slot], now);
      pipe().accept({slot, w.out}, now, w.cycles, w.interval, std::move(w.wait));
      return true;
    } else if constexpr (K == UnitKind::Mac) {
      Fifo& in = e.fifo(FifoId::Intersect);
      if (!in.visible()) return false;
      const uint32_t slot = in.read(now);
      if (e.free_results_.empty()) {
        e.results_.emplace_back();
        e.free_results_.push_back(uint32_t(e.results_.size() - 1));
      }
      const uint32_t result = e.free_results_.back();
      e.free_results_.pop_back();
      MacResult& m = e.results_[result];
      m.r = e.slots_[slot];
      e.free_slots_.push_back(slot);  // the ray travels with its MAC result now
      Work w = e.macs_[size_t(index())].take(m, now);
      if (!e.clocked_macs_.empty()) e.clocked_job(size_t(index()), m, w.cycles, now);
      pipe().accept({result, w.out}, now, w.cycles, w.interval, std::move(w.wait));
      return true;
    } else if constexpr (K == UnitKind::Root) {
      Fifo& in = e.fifo(FifoId::Root, size_t(index()));
      if (!in.visible()) return false;
      const uint32_t result = in.read(now);
      Work w = e.roots_[size_t(index())].take(e.results_[result], now);
      pipe().accept({result, w.out}, now, w.cycles, w.interval, std::move(w.wait));
      return true;
    } else {
      Fifo& in = e.fifo(FifoId::Shade);
      if (!in.visible()) return false;
      const uint32_t slot = in.read(now);
      const MachineRay& r = e.slots_[slot];
      Work w = e.shading_.take(r, e.frame_[r.slot], e.ids_[r.slot], now);
      pipe().accept({slot, w.out}, now, w.cycles, w.interval, std::move(w.wait));
      return true;
    }
  }

  bool wait_for_input() {
    if constexpr (K == UnitKind::FrontBuffer) {
      return e.front_.wait(now);
    } else if constexpr (RayStage<K>::value || K == UnitKind::Mac) {
      e.waiting_[size_t(K)].idle(index());
    } else {
      place.waiting = true;
    }
    return true;
  }

  void want(uint64_t t) { e.want(u, t); }
};

// Out of line: the fast MAC's operations stay small enough for wake() to inline every unit's.
[[gnu::noinline]] void PeEngine::clocked_job(size_t lane, const MacResult& m, uint64_t cycles,
                                             uint64_t now) {
  clocked_macs_[lane].start(now, mac_job(*pe_.image, m.r, m.plan), cycles);
}

[[gnu::noinline]] void PeEngine::clocked_result(size_t lane, uint32_t result, bool full,
                                                uint64_t now) {
  // As in the modules (machine/intersection_module.cpp): the clocked sums, checked against the
  // fast model's, are the ones the root unit takes, and a result that cannot leave holds the
  // clocked MAC.
  EdgeByEdgeMac& clocked = clocked_macs_[lane];
  const std::string differs = clocked.check(now, results_[result], pe_.image->mem32.has_value());
  if (!differs.empty()) throw std::logic_error(differs);
  clocked.stall(now, full);
}

void PeEngine::wake(size_t unit, uint64_t now) {
  // One instance of the step per kind of unit: its operations inline, no switch per call.
  Place& place = places_[unit];
  auto step = [&](auto ops) { rtm::step_unit(place.pipe, now, cycle_, pe_.memory.get(), ops); };
  switch (place.kind) {
    case UnitKind::FrontBuffer:
      return step(Ops<UnitKind::FrontBuffer>{*this, unit, now, place});
#define RTM_RAY_STAGE_CASE(kind, Class) \
  case UnitKind::kind:                  \
    return step(Ops<UnitKind::kind>{*this, unit, now, place});
      RTM_RAY_STAGES(RTM_RAY_STAGE_CASE)
#undef RTM_RAY_STAGE_CASE
    case UnitKind::Mac:
      return step(Ops<UnitKind::Mac>{*this, unit, now, place});
    case UnitKind::Root:
      return step(Ops<UnitKind::Root>{*this, unit, now, place});
    case UnitKind::Shading:
      return step(Ops<UnitKind::Shading>{*this, unit, now, place});
  }
}

/// The front buffer's operations for FrontBufferPolicy::carry_out.
struct PeEngine::FrontOps {
  PeEngine& e;
  uint64_t now;

  bool read_end() {
    Fifo& ends = e.fifo(FifoId::Ends);
    if (!ends.visible()) return false;
    ends.read(now);
    return true;
  }
  bool read(FifoId id, uint32_t& slot) {
    Fifo& in = e.fifo(id);
    if (!in.visible()) return false;
    slot = in.read(now);
    return true;
  }
  void drained() {}
  uint32_t primary(size_t n) { return e.new_ray(primary_ray(e.pe_, e.rays_, n)); }
  void dispatch(uint32_t slot, uint64_t cycles, uint8_t from, MemoryWait&& wait) {
    e.front_.dispatched(now, e.slots_[slot].id, cycles, from);
    e.places_[e.place(UnitKind::FrontBuffer)].pipe.accept(
        {slot, {}}, now, cycles, e.front_.interval(cycles), std::move(wait));
  }
  void want(uint64_t t) { e.want(e.place(UnitKind::FrontBuffer), t); }
  void finished() {}
  void ask_for_tile() { e.asked_at_ = now; }
  void frame_ended() { e.frame_ended_at_ = now; }
};

/// Shading's operations for ShadingWriter: `ray` is the oldest shaded ray's slot.
struct PeEngine::ShadingOps {
  PeEngine& e;
  uint32_t ray;
  uint64_t now;

  bool write_end(const Output& o) {
    return e.emit(o, e.slots_[ray], kNoSlot, UnitKind::Shading, 0, now);
  }
  uint32_t make(size_t k) { return e.new_ray(e.shading_.spawn(e.slots_[ray], k)); }
  bool write(const Output& o, uint32_t child) {
    return e.emit(o, e.slots_[child], child, UnitKind::Shading, 0, now);
  }
};

// ---- statistics ----

FifoStatsList PeEngine::fifo_stats(uint64_t now, double seconds_per_tick) {
  return rtm::fifo_stats(
      pe_, now, seconds_per_tick,
      [&](const FifoSpec& f, int lane) -> FifoMeter& { return fifo(f.id, size_t(lane)).meter; });
}

std::string PeEngine::occupancy_report() {
  return rtm::occupancy_report(pe_, front_, [&](const FifoSpec& f, int lane) -> FifoMeter& {
    return fifo(f.id, size_t(lane)).meter;
  });
}

}  // namespace rtm
