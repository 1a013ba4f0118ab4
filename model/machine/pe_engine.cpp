#include "machine/pe_engine.h"

#include <algorithm>
#include <sstream>

namespace rtm {

std::string engine_unsupported(const MachineConfig& c, bool tracing) {
  if (c.pe_simulation == MachineConfig::PeSimulation::Modules) return "pe_simulation = modules";
  if (c.timing != Timing::Fast) return "clocked timing runs the MAC on a clock";
  if (c.arbitration != MachineConfig::Arbitration::Ranked)
    return "arbitration = kernel leaves the same-cycle order to SystemC";
  if (c.flow_control != FlowControl::Credits) return "flow_control = none can deadlock, which the modules report";
  if (c.dda_step_cycles == 0 || c.shade_cycles == 0 || c.accumulate_cycles == 0)
    return "a unit taking zero cycles acts within the instant it started";
  if (tracing) return "a waveform traces the modules' signals";
  return "";
}

PeEngine::Fifo::Fifo(const FifoSpec& spec, int depth, std::vector<Fifo*>* touched)
    : name(spec.name), ring(size_t(depth)), meter(spec.kind, depth), touched_list(touched) {}

PeEngine::PeEngine(PeState& pe, std::vector<PixelSum>& frame, std::vector<int32_t>& ids, const std::vector<Ray>& rays,
                   size_t rays_expected)
    : pe_(pe),
      frame_(frame),
      ids_(ids),
      rays_(rays),
      cycle_(pe.cycle),
      front_(pe, rays_expected),
      shading_(pe),
      lanes_(size_t(pe.config.intersection_units)),
      mac0_(kSearch + size_t(pe.config.search_units)),
      root0_(mac0_ + lanes_),
      idle_macs_(pe.config.intersection_units) {
  for (const FifoSpec& f : fifo_table()) {
    if (!pe.units.has(f)) continue;
    const int depth = pe.config.*f.depth;
    if (f.per_lane) {
      for (size_t lane = 0; lane < lanes_; ++lane) in_order_.push_back(&root_fifo_.emplace_back(f, depth, &touched_));
    } else {
      Fifo* fifo = fifos_by_id_[size_t(f.id)] = &fifos_.emplace_back(f, depth, &touched_);
      in_order_.push_back(fifo);
      fifo->feeds_front = std::count(f.readers.begin(), f.readers.end(), UnitKind::FrontBuffer) > 0;
      if (f.payload == Payload::Ray && fifo->feeds_front) front_inputs_.emplace_back(fifo, f.returns_credit);
    }
  }
  due_at_.assign(root0_ + lanes_, kNever);
  due_.resize(due_at_.size());
  for (int k = 0; k < pe.config.search_units; ++k) search_.emplace_back(pe, k);
  for (size_t u = mac0_; u-- > kSearch;) idle_search_.push_back(u);
  for (size_t lane = 0; lane < lanes_; ++lane) {
    macs_.emplace_back(pe, int(lane));
    roots_.emplace_back(pe, int(lane));
  }
  front_loop(0);
}

// ---- the event loop ----

uint64_t PeEngine::next_instant() {
  uint64_t next = pending_step_;
  due_now_.clear();
  for (size_t u = 0; u < due_at_.size(); ++u) {
    const uint64_t at = due_at_[u];
    if (at > next) continue;
    if (at < next) {
      next = at;
      due_now_.clear();
    }
    if (at != kNever) due_now_.push_back(u);
  }
  return next;
}

bool PeEngine::idle() const {
  return pending_step_ == kNever &&
         std::all_of(due_at_.begin(), due_at_.end(), [](uint64_t at) { return at == kNever; });
}

void PeEngine::run_before(uint64_t t) {
  for (uint64_t next; (next = next_instant()) < t;) step(next);
}

void PeEngine::rays_arrived(uint64_t t, size_t n) {
  front_.primaries_arrived(n);
  front_poked_ = true;
  pending_step_ = t;
}

void PeEngine::schedule(size_t unit, uint64_t at, uint32_t item, Output out) {
  // Root units go by their lane: each takes only its own MAC's results, and the modules rank
  // them so (machine/pe_context.h).
  const UnitKind kind = kind_at(unit);
  const uint64_t rank = uint64_t(kind) + (kind == UnitKind::Root ? unit - root0_ : 0);
  due_at_[unit] = at;
  Due& d = due_[unit];
  d.order = rank << 48 | seq_++;
  d.item = item;
  d.out = out;
}

void PeEngine::step(uint64_t now) {
  if (pending_step_ == now) pending_step_ = kNever;
  // The units whose work ends now (found by next_instant), in rank order; their next work ends later.
  for (size_t i = 1; i < due_now_.size(); ++i)  // a few at most: insertion sort
    for (size_t j = i; j > 0 && due_[due_now_[j]].order < due_[due_now_[j - 1]].order; --j)
      std::swap(due_now_[j], due_now_[j - 1]);
  for (size_t u : due_now_) {
    const Due d = due_[u];
    due_at_[u] = kNever;
    wake(u, d, now);
  }
  // What they wrote becomes visible. The front buffer is poked by a write to any of its inputs.
  bool poked = front_poked_;
  front_poked_ = false;
  for (Fifo* f : touched_) {
    poked = poked || (f->written && f->feeds_front);
    f->visible = f->count;
    f->written = false;
    f->reads_now = 0;
  }
  // Idle units take it, and the front buffer drains its inputs if it was waiting.
  take_inputs(now);
  if (front_waiting_ && !front_.finished() && poked) {
    front_.woke(now);
    front_loop(now);
  }
  // Places freed by reads are there for the next instant's writers.
  for (Fifo* f : touched_) {
    f->reads_now = 0;
    f->touched = false;
  }
  touched_.clear();
}

void PeEngine::take_inputs(uint64_t now) {
  Fifo& search_in = fifo(FifoId::Search);
  while (!idle_search_.empty() && search_in.visible > 0) {
    const size_t u = idle_search_.back();
    idle_search_.pop_back();
    search_start(u, search_in.read(now), now);
  }
  Fifo& mac_in = fifo(FifoId::Intersect);
  while (idle_macs_.any_idle() && mac_in.visible > 0) mac_start(size_t(idle_macs_.take()), mac_in.read(now), now);
  // A unit with nothing due is idle.
  for (size_t lane = 0; lane < lanes_; ++lane)
    if (due_at_[root0_ + lane] == kNever && root_fifo_[lane].visible > 0) root_start(lane, root_fifo_[lane].read(now), now);
  Fifo& shade_in = fifo(FifoId::Shade);
  if (due_at_[kShading] == kNever && shade_in.visible > 0) shade_start(shade_in.read(now), now);
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

inline bool PeEngine::emit(const Output& o, const MachineRay& r, uint32_t slot, UnitKind kind, int index, uint64_t now) {
  Fifo& f = fifo(o.fifo);
  if (f.full()) return false;
  const uint32_t id = r.id;
  if (o.what == Output::What::End) {
    f.write(id, now);
    if (slot != kNoSlot) free_slots_.push_back(slot);
  } else {
    f.write(slot != kNoSlot ? slot : new_ray(r), now);
  }
  record_put(pe_, now, kind, index, id, o);
  return true;
}

// ---- the units: each writes its result when its work ends (one cycle later again while the
// FIFO is full, as the modules' put() does), then takes its next item ----

void PeEngine::wake(size_t unit, const Due& d, uint64_t now) {
  const uint64_t retry = now + cycle_;
  switch (kind_at(unit)) {
    case UnitKind::FrontBuffer: {
      if (front_aligning_) {
        front_aligning_ = false;
        primary(now);
        return;
      }
      const Output to_search{FifoId::Search, Output::What::Item};
      if (!emit(to_search, slots_[front_ray_], front_ray_, UnitKind::FrontBuffer, 0, now)) return schedule(kFront, retry);
      front_loop(now);
      return;
    }

    case UnitKind::Search: {
      const size_t k = unit - kSearch;
      if (!emit(d.out, slots_[d.item], d.item, UnitKind::Search, int(k), now))
        return schedule(unit, retry, d.item, d.out);
      Fifo& in = fifo(FifoId::Search);
      if (in.visible > 0)
        search_start(unit, in.read(now), now);
      else
        idle_search_.push_back(unit);
      return;
    }

    case UnitKind::Mac: {
      const size_t lane = unit - mac0_;
      Fifo& out = root_fifo_[lane];
      if (out.full()) return schedule(unit, retry, d.item, d.out);
      out.write(d.item, now);
      record_put(pe_, now, UnitKind::Mac, int(lane), results_[d.item].r.id, d.out);
      Fifo& in = fifo(FifoId::Intersect);
      if (in.visible > 0)
        mac_start(lane, in.read(now), now);
      else
        idle_macs_.idle(int(lane));
      return;
    }

    case UnitKind::Root: {
      const size_t lane = unit - root0_;
      if (!emit(d.out, results_[d.item].r, kNoSlot, UnitKind::Root, int(lane), now))
        return schedule(unit, retry, d.item, d.out);
      free_results_.push_back(d.item);
      if (root_fifo_[lane].visible > 0) root_start(lane, root_fifo_[lane].read(now), now);
      return;
    }

    case UnitKind::Shading:
      // Its outputs in order; a spawned ray is made (numbered) before it waits for room, as in
      // the module.
      for (; shade_next_ < shading_.outputs(); ++shade_next_) {
        const Output o = shading_.output(shade_next_);
        if (shade_next_ == 0) {
          if (!emit(o, slots_[shade_ray_], kNoSlot, UnitKind::Shading, 0, now)) return schedule(kShading, retry);
          continue;
        }
        if (!shade_child_made_) {
          shade_child_ = new_ray(shading_.spawn(slots_[shade_ray_], shade_next_));
          shade_child_made_ = true;
        }
        if (!emit(o, slots_[shade_child_], shade_child_, UnitKind::Shading, 0, now)) return schedule(kShading, retry);
        shade_child_made_ = false;
      }
      free_slots_.push_back(shade_ray_);
      if (fifo(FifoId::Shade).visible > 0) shade_start(fifo(FifoId::Shade).read(now), now);
      return;
  }
}

void PeEngine::front_loop(uint64_t now) {
  Fifo& ends = fifo(FifoId::Ends);
  while (ends.visible > 0) {
    ends.read(now);
    front_.ended();
  }
  for (const auto& [in, returns_credit] : front_inputs_)
    while (in->visible > 0) returns_credit ? front_.returned(in->read(now)) : front_.spawned(in->read(now));
  using Next = FrontBufferPolicy<uint32_t>::Next;
  front_waiting_ = false;
  switch (front_.next()) {
    case Next::Queued: {
      uint64_t cycles = 0;
      bool spilled = false;
      const uint32_t slot = front_.pop_queued(cycles, spilled);
      return dispatch(slot, cycles, spilled ? kFromSpill : kFromQueue, now);
    }
    case Next::Primary:
      // Rays from the host arrive between PE clock edges.
      if (const uint64_t off = now % cycle_) {
        front_aligning_ = true;
        return schedule(kFront, now + cycle_ - off);
      }
      return primary(now);
    case Next::Finished:
      return front_.finish(now);
    case Next::Wait:
      front_.wait(now);
      front_waiting_ = true;
      return;
  }
}

void PeEngine::primary(uint64_t now) {
  uint64_t cycles = 0;
  const size_t i = front_.pop_primary(now, cycles);
  const uint32_t slot = new_ray(primary_ray(pe_, rays_, i));
  dispatch(slot, cycles, kFromHost, now);
}

void PeEngine::dispatch(uint32_t slot, uint64_t cycles, uint8_t from, uint64_t now) {
  front_.dispatched(now, slots_[slot].id, cycles, from);
  front_ray_ = slot;
  schedule(kFront, now + cycles * cycle_);
}

void PeEngine::search_start(size_t unit, uint32_t slot, uint64_t now) {
  const Work w = search_[unit - kSearch].take(slots_[slot], now);
  schedule(unit, now + w.cycles * cycle_, slot, w.out);
}

void PeEngine::mac_start(size_t lane, uint32_t slot, uint64_t now) {
  if (free_results_.empty()) {
    results_.emplace_back();
    free_results_.push_back(uint32_t(results_.size() - 1));
  }
  const uint32_t result = free_results_.back();
  free_results_.pop_back();
  MacResult& m = results_[result];
  m.r = slots_[slot];
  free_slots_.push_back(slot);  // the ray travels with its MAC result now
  const Work w = macs_[lane].take(m, now);
  schedule(mac0_ + lane, now + w.cycles * cycle_, result, w.out);
}

void PeEngine::root_start(size_t lane, uint32_t result, uint64_t now) {
  const Work w = roots_[lane].take(results_[result], now);
  schedule(root0_ + lane, now + w.cycles * cycle_, result, w.out);
}

void PeEngine::shade_start(uint32_t slot, uint64_t now) {
  shade_ray_ = slot;
  const MachineRay& r = slots_[slot];
  const uint64_t cycles = shading_.take(r, frame_[r.slot], ids_[r.slot], now);
  shade_next_ = 0;
  schedule(kShading, now + cycles * cycle_);
}

// ---- statistics ----

std::vector<std::pair<std::string, const FifoStats*>> PeEngine::fifo_stats(uint64_t now) {
  std::vector<std::pair<std::string, const FifoStats*>> out;
  for (Fifo* f : in_order_) out.emplace_back(f->name, &f->meter.close(now));
  return out;
}

std::string PeEngine::occupancy_report() const {
  std::ostringstream s;
  s << front_.waiting() << " rays waiting in the front buffer, " << front_.in_flight() << " past it;";
  for (const Fifo* f : in_order_) s << " " << f->name << " " << f->meter.occupancy << "/" << f->meter.stats.depth;
  return s.str();
}

}  // namespace rtm
